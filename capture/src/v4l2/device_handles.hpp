#pragma once
// RAII for what a V4L2 stream holds: the open device and each mapping.
#include <cstddef>
#include <memory>
#include <utility>

#include "spinewatch/capture/v4l2_device.hpp"

namespace spinewatch::v4l2 {

class DeviceFd {
 public:
  DeviceFd() = default;
  DeviceFd(std::shared_ptr<V4l2Device> device, int fd) : device_(std::move(device)), fd_(fd) {}
  ~DeviceFd() { reset(); }
  DeviceFd(DeviceFd&& o) noexcept : device_(std::move(o.device_)), fd_(std::exchange(o.fd_, -1)) {}
  DeviceFd& operator=(DeviceFd&& o) noexcept {
    if (this != &o) {
      reset();
      device_ = std::move(o.device_);
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  void reset() {
    if (fd_ >= 0) device_->close(fd_);
    fd_ = -1;
  }

 private:
  std::shared_ptr<V4l2Device> device_;
  int fd_ = -1;
};

class MappedBuffer {
 public:
  MappedBuffer(std::shared_ptr<V4l2Device> device, void* address, std::size_t length)
      : device_(std::move(device)), address_(address), length_(length) {}
  ~MappedBuffer() {
    if (address_) device_->munmap(address_, length_);
  }
  MappedBuffer(MappedBuffer&& o) noexcept
      : device_(std::move(o.device_)), address_(std::exchange(o.address_, nullptr)), length_(o.length_) {}
  MappedBuffer& operator=(MappedBuffer&&) = delete;
  MappedBuffer(const MappedBuffer&) = delete;

  const std::uint8_t* data() const { return static_cast<const std::uint8_t*>(address_); }
  std::size_t length() const { return length_; }

 private:
  std::shared_ptr<V4l2Device> device_;
  void* address_ = nullptr;
  std::size_t length_ = 0;
};

}  // namespace spinewatch::v4l2

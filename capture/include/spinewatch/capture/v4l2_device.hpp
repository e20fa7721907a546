#pragma once
// The system calls of V4L2 capture, behind a small interface: the camera
// code (every ioctl of it) runs unchanged against FakeV4l2Device in tests.
// Calls behave like the system calls: −1 (or MAP_FAILED) and errno on failure.
#include <poll.h>
#include <sys/types.h>

#include <cstddef>
#include <memory>

namespace spinewatch {

class V4l2Device {
 public:
  virtual ~V4l2Device() = default;
  virtual int open(const char* path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  virtual void* mmap(std::size_t length, int prot, int flags, int fd, off_t offset) = 0;
  virtual int munmap(void* address, std::size_t length) = 0;
  // `fds` may mix device descriptors and ordinary ones (the wake-up eventfd).
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

// The kernel's (ioctl retried on EINTR).
std::shared_ptr<V4l2Device> system_v4l2_device();

}  // namespace spinewatch

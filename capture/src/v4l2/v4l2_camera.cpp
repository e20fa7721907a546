#include "spinewatch/capture/v4l2_camera.hpp"

#include <linux/videodev2.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <spdlog/spdlog.h>

#include "spinewatch/frames/clock.hpp"
#include "stream_session.hpp"

namespace spinewatch {
namespace {

// Keeps a V4L2 buffer out of the driver's queue while a Frame uses it.
class BufferLease {
 public:
  BufferLease(std::shared_ptr<v4l2::StreamSession> session, std::uint32_t index)
      : session_(std::move(session)), index_(index) {}
  ~BufferLease() { session_->requeue(index_); }
  BufferLease(const BufferLease&) = delete;
  BufferLease& operator=(const BufferLease&) = delete;

 private:
  std::shared_ptr<v4l2::StreamSession> session_;
  std::uint32_t index_;
};

}  // namespace

V4l2Camera::V4l2Camera(V4l2CameraOptions options, std::shared_ptr<V4l2Device> device)
    : options_(std::move(options)),
      name_(options_.name.empty() ? options_.path : options_.name),
      device_(std::move(device)),
      wake_fd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)),
      backoff_(options_.retry_initial) {}

V4l2Camera::~V4l2Camera() {
  if (session_) session_->shutdown();  // frames still out keep the mappings alive
  session_.reset();
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

Status V4l2Camera::open_session() {
  auto session = v4l2::StreamSession::open(device_, options_, name_);
  if (!session) return session.error();
  session_ = std::move(session.value());
  {
    std::lock_guard lock(format_mutex_);
    format_ = session_->format();
    fps_ = session_->fps();
  }
  last_driver_sequence_.reset();
  sequence_base_ = next_sequence_;
  last_frame_ns_ = monotonic_now_ns();
  streaming_.store(true);
  spdlog::info("{}: streaming {} at {:.2f} fps, {} buffers", name_, describe(session_->format()), session_->fps(),
               session_->buffer_count());
  return Ok{};
}

Status V4l2Camera::start() {
  if (wake_fd_ < 0) return Error{fmt::format("{}: eventfd: {}", name_, std::strerror(errno))};
  return open_session();
}

void V4l2Camera::stop() {
  stopped_.store(true);
  const std::uint64_t one = 1;
  [[maybe_unused]] auto n = ::write(wake_fd_, &one, sizeof one);
}

void V4l2Camera::lose_device(const std::string& why) {
  spdlog::error("{}: device lost ({}); reopening with backoff", name_, why);
  losses_.fetch_add(1);
  session_->shutdown();
  session_.reset();
  streaming_.store(false);
  backoff_ = options_.retry_initial;
  retry_at_ns_ = monotonic_now_ns() + std::chrono::nanoseconds(backoff_).count();
}

void V4l2Camera::try_reopen() {
  auto opened = open_session();
  if (opened) {
    restarts_.fetch_add(1);
    spdlog::info("{}: device back after a loss", name_);
    return;
  }
  spdlog::debug("{}", opened.error().message);  // the loss was logged once; retries are quiet
  backoff_ = std::min(backoff_ * 2, options_.retry_max);
  retry_at_ns_ = monotonic_now_ns() + std::chrono::nanoseconds(backoff_).count();
}

void V4l2Camera::check_watchdog(std::int64_t now_ns) {
  if (options_.watchdog_s <= 0 || stalled_.load()) return;
  if (now_ns - last_frame_ns_ > static_cast<std::int64_t>(options_.watchdog_s * 1e9)) {
    stalled_.store(true);
    stalls_.fetch_add(1);
    spdlog::warn("{}: no frame for {:g} s", name_, options_.watchdog_s);
  }
}

std::optional<Frame> V4l2Camera::next(std::chrono::milliseconds timeout) {
  const std::int64_t deadline = monotonic_now_ns() + std::chrono::nanoseconds(timeout).count();
  while (!stopped_.load()) {
    const std::int64_t now = monotonic_now_ns();
    if (now >= deadline && timeout.count() >= 0) {
      check_watchdog(now);
      return std::nullopt;
    }
    if (!session_ && now >= retry_at_ns_) {
      try_reopen();
      continue;
    }
    // While the device is away, sleep on the wake-up fd until the next retry.
    std::int64_t wait_ns = timeout.count() >= 0 ? deadline - now : 60'000'000'000;  // negative: no timeout
    if (!session_) wait_ns = std::min(wait_ns, retry_at_ns_ - now);
    if (options_.watchdog_s > 0 && !stalled_.load()) {
      wait_ns = std::min(wait_ns, last_frame_ns_ + static_cast<std::int64_t>(options_.watchdog_s * 1e9) - now + 1'000'000);
    }
    pollfd fds[2] = {{wake_fd_, POLLIN, 0}, {session_ ? session_->fd() : -1, POLLIN, 0}};
    const int wait_ms = static_cast<int>(std::clamp<std::int64_t>((wait_ns + 999'999) / 1'000'000, 0, 60'000));
    const int n = device_->poll(fds, session_ ? 2 : 1, wait_ms);
    if (n < 0 && errno != EINTR) {
      spdlog::error("{}: poll: {}", name_, std::strerror(errno));
      return std::nullopt;
    }
    if (fds[0].revents & POLLIN) return std::nullopt;  // stop()
    check_watchdog(monotonic_now_ns());
    if (!session_ || n <= 0) continue;
    if (fds[1].revents & (POLLERR | POLLHUP | POLLNVAL)) {
      lose_device("POLLERR");
      continue;
    }
    if (!(fds[1].revents & POLLIN)) continue;

    v4l2::Dequeued buf;
    if (const int err = session_->dequeue(buf); err != 0) {
      if (err == EAGAIN || err == EINTR) continue;
      lose_device(std::strerror(err));
      continue;
    }
    if (last_driver_sequence_ && buf.sequence > *last_driver_sequence_ + 1) {
      dropped_gap_.fetch_add(buf.sequence - *last_driver_sequence_ - 1);
    }
    last_driver_sequence_ = buf.sequence;
    next_sequence_ = sequence_base_ + buf.sequence + 1;
    last_frame_ns_ = monotonic_now_ns();
    if (stalled_.exchange(false)) spdlog::info("{}: frames again", name_);

    // The lease requeues the buffer when the Frame (or this early return) lets go of it.
    auto lease = std::make_shared<BufferLease>(session_, buf.index);
    const FrameFormat& format = session_->format();
    if ((buf.flags & V4L2_BUF_FLAG_ERROR) || (buf.bytesused != 0 && buf.bytesused < format.frame_bytes())) {
      dropped_error_.fetch_add(1);
      continue;
    }
    std::int64_t t_ns = buf.timestamp_ns;
    if ((buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
      // Without a monotonic driver stamp the dequeue time is the best we have.
      if (!warned_clock_) spdlog::warn("{}: the driver's timestamps are not CLOCK_MONOTONIC; using dequeue time", name_);
      warned_clock_ = true;
      t_ns = last_frame_ns_;
    }
    frames_.fetch_add(1);
    return Frame(format, FrameInfo{sequence_base_ + buf.sequence, t_ns}, std::move(lease),
                 session_->bytes(buf.index));
  }
  return std::nullopt;
}

CameraCounters V4l2Camera::counters() const {
  return {frames_.load(), dropped_error_.load(), dropped_gap_.load(), restarts_.load(), stalls_.load(), losses_.load()};
}

FrameFormat V4l2Camera::format() const {
  std::lock_guard lock(format_mutex_);
  return format_;
}

double V4l2Camera::fps() const {
  std::lock_guard lock(format_mutex_);
  return fps_;
}

}  // namespace spinewatch

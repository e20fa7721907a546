#include "spinewatch/capture/libcamera_camera.hpp"

#include <sys/mman.h>

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>

#include <fmt/format.h>
#include <libcamera/camera.h>
#include <libcamera/control_ids.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/request.h>
#include <libcamera/stream.h>
#include <spdlog/spdlog.h>

#include "camera_manager.hpp"

namespace spinewatch {
namespace {

libcamera::PixelFormat to_libcamera(PixelFormat f) {
  return f == PixelFormat::GREY ? libcamera::formats::R8 : libcamera::formats::YUYV;
}

std::string describe(const libcamera::StreamConfiguration& c) {
  return fmt::format("{} {}", c.pixelFormat.toString(), c.size.toString());
}

// A read-only mapping of one buffer's dmabuf; unmapped when it goes.
class BufferMapping {
 public:
  BufferMapping(void* address, std::size_t length) : address_(address), length_(length) {}
  ~BufferMapping() {
    if (address_ != MAP_FAILED) ::munmap(address_, length_);
  }
  BufferMapping(const BufferMapping&) = delete;
  BufferMapping& operator=(const BufferMapping&) = delete;
  const std::uint8_t* data() const { return static_cast<const std::uint8_t*>(address_); }

 private:
  void* address_;
  std::size_t length_;
};

}  // namespace

struct LibcameraCamera::State {
  LibcameraCameraOptions options;
  std::string name;
  std::shared_ptr<libcamera::CameraManager> manager;  // outlives the camera
  std::shared_ptr<libcamera::Camera> camera;
  std::unique_ptr<libcamera::CameraConfiguration> config;
  libcamera::Stream* stream = nullptr;
  std::unique_ptr<libcamera::FrameBufferAllocator> allocator;
  std::map<const libcamera::FrameBuffer*, std::unique_ptr<BufferMapping>> mappings;
  std::vector<std::unique_ptr<libcamera::Request>> requests;
  FrameFormat format{};
  double fps = 0.0;
  bool started = false;

  std::mutex mutex;  // completed, stopped
  std::condition_variable ready;
  std::deque<libcamera::Request*> completed;
  bool stopped = false;
  std::atomic<bool> running{false};  // requests may be queued

  std::optional<unsigned> last_sequence;  // next()'s thread only
  std::atomic<std::uint64_t> frames{0}, dropped_error{0}, dropped_gap{0}, losses{0};

  ~State() {
    // Last lease gone: requests before the buffers they hold, buffers before the camera.
    requests.clear();
    mappings.clear();
    allocator.reset();
    if (camera) camera->release();
  }

  // libcamera's thread.
  void on_complete(libcamera::Request* request) {
    if (request->status() == libcamera::Request::RequestCancelled) return;
    {
      std::lock_guard lock(mutex);
      if (stopped) return;
      completed.push_back(request);
    }
    ready.notify_one();
  }

  // libcamera's thread: the device went away (unplugged, its driver unbound).
  // libcamera does not give a camera back once disconnected (a new Camera is
  // announced by cameraAdded instead), so this camera delivers nothing more:
  // counted and logged once here; the consumer sees `losses` grow and marks
  // the gap (the daemon's pair source publishes it as a lost line).
  void on_disconnected() {
    running.store(false);  // no request goes back to a camera that is gone
    losses.fetch_add(1);
    spdlog::error("{}: camera disconnected; it delivers no more frames until the daemon reopens it", name);
  }

  // When a frame's last copy goes: the buffer is free, the request goes back to the camera.
  void requeue(libcamera::Request* request) {
    if (!running.load()) return;
    request->reuse(libcamera::Request::ReuseBuffers);
    if (const int err = camera->queueRequest(request); err < 0 && running.load())
      spdlog::warn("{}: a request could not be queued again: {}", name, std::strerror(-err));
  }

  void shutdown() {
    {
      std::lock_guard lock(mutex);
      stopped = true;
      completed.clear();
    }
    ready.notify_all();
    running.store(false);
    if (started) {
      camera->stop();
      camera->requestCompleted.disconnect(this);
      camera->disconnected.disconnect(this);
      started = false;
    }
  }

  Status configure();
  Status map_buffers();
  libcamera::ControlList start_controls();
};

namespace {

// A frame's hold on its request: the request goes back to the camera when
// the last copy of the frame is released.
class RequestLease {
 public:
  RequestLease(std::shared_ptr<LibcameraCamera::State> state, libcamera::Request* request)
      : state_(std::move(state)), request_(request) {}
  ~RequestLease() { state_->requeue(request_); }
  RequestLease(const RequestLease&) = delete;
  RequestLease& operator=(const RequestLease&) = delete;

 private:
  std::shared_ptr<LibcameraCamera::State> state_;
  libcamera::Request* request_;
};

}  // namespace

Status LibcameraCamera::State::configure() {
  config = camera->generateConfiguration({libcamera::StreamRole::Viewfinder});
  if (!config || config->empty()) return Error{fmt::format("{}: libcamera offers no viewfinder stream", name)};
  libcamera::StreamConfiguration& c = config->at(0);
  const libcamera::PixelFormat wanted = to_libcamera(options.pixel_format);
  const libcamera::Size size(options.width, options.height);
  c.pixelFormat = wanted;
  c.size = size;
  c.bufferCount = options.buffers;
  const std::string asked = describe(c);
  switch (config->validate()) {
    case libcamera::CameraConfiguration::Invalid:
      return Error{fmt::format("{}: libcamera rejects the configuration {}", name, asked)};
    case libcamera::CameraConfiguration::Adjusted:
      if (c.pixelFormat != wanted || c.size != size)
        return Error{fmt::format("{}: the camera cannot deliver {} (the nearest it offers: {}); "
                                 "set cameras.pixel_format / width / height to what it can do",
                                 name, asked, describe(c))};
      break;
    case libcamera::CameraConfiguration::Valid:
      break;
  }
  if (const int err = camera->configure(config.get()); err < 0)
    return Error{fmt::format("{}: configuring {} failed: {}", name, asked, std::strerror(-err))};
  stream = c.stream();
  format = FrameFormat{options.pixel_format, c.size.width, c.size.height, c.stride};
  return Ok{};
}

Status LibcameraCamera::State::map_buffers() {
  allocator = std::make_unique<libcamera::FrameBufferAllocator>(camera);
  if (const int err = allocator->allocate(stream); err < 0)
    return Error{fmt::format("{}: cannot allocate buffers: {}", name, std::strerror(-err))};
  for (const auto& buffer : allocator->buffers(stream)) {
    const auto& planes = buffer->planes();
    // YUYV and R8 are single-plane formats.
    if (planes.empty() || planes[0].length < format.frame_bytes())
      return Error{fmt::format("{}: a buffer is smaller than a {} frame", name, describe(format))};
    const std::size_t length = planes[0].offset + planes[0].length;
    void* address = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, planes[0].fd.get(), 0);
    if (address == MAP_FAILED) return Error{fmt::format("{}: cannot map a buffer: {}", name, std::strerror(errno))};
    mappings[buffer.get()] = std::make_unique<BufferMapping>(address, length);
    auto request = camera->createRequest();
    if (!request) return Error{fmt::format("{}: cannot create a request", name)};
    if (const int err = request->addBuffer(stream, buffer.get()); err < 0)
      return Error{fmt::format("{}: cannot attach a buffer to a request: {}", name, std::strerror(-err))};
    requests.push_back(std::move(request));
  }
  return Ok{};
}

// Frame rate, exposure and gain, where the camera has the control; what it
// lacks is a warning, as with V4L2.
libcamera::ControlList LibcameraCamera::State::start_controls() {
  namespace controls = libcamera::controls;
  const auto& available = camera->controls();
  auto has = [&](const libcamera::ControlId& id) { return available.count(id.id()) > 0; };
  libcamera::ControlList list(available);
  fps = options.fps;
  if (has(controls::FrameDurationLimits)) {
    const std::int64_t period_us = std::llround(1e6 / options.fps);
    list.set(controls::FrameDurationLimits, {period_us, period_us});
  } else {
    spdlog::warn("{}: no FrameDurationLimits control; the camera chooses its frame rate", name);
  }
  if (options.exposure_us > 0) {
    if (has(controls::ExposureTime)) {
      if (has(controls::AeEnable)) list.set(controls::AeEnable, false);
      list.set(controls::ExposureTime, options.exposure_us);
    } else {
      spdlog::warn("{}: no ExposureTime control; exposure stays automatic", name);
    }
  }
  if (options.gain >= 0) {
    if (!has(controls::AnalogueGain))
      spdlog::warn("{}: no AnalogueGain control; gain stays automatic", name);
    else if (options.gain < 1)
      spdlog::warn("{}: cameras.gain {} ignored: libcamera's AnalogueGain is a multiplier, at least 1", name,
                   options.gain);
    else
      list.set(controls::AnalogueGain, static_cast<float>(options.gain));
  }
  return list;
}

Result<std::unique_ptr<LibcameraCamera>> LibcameraCamera::open(LibcameraCameraOptions options) {
  auto manager = lc::shared_camera_manager();
  if (!manager) return manager.error();
  auto camera = (*manager)->get(options.id);
  if (!camera) {
    std::string ids;
    for (const auto& c : (*manager)->cameras()) ids += (ids.empty() ? "" : ", ") + c->id();
    return Error{fmt::format("libcamera camera \"{}\": not found (cameras: {})", options.id,
                             ids.empty() ? "none" : ids)};
  }
  if (const int err = camera->acquire(); err < 0)
    return Error{fmt::format("libcamera camera \"{}\": cannot be acquired (in use?): {}", options.id,
                             std::strerror(-err))};
  auto state = std::make_shared<State>();
  state->name = options.name.empty() ? options.id : options.name;
  state->options = std::move(options);
  state->manager = std::move(manager).value();
  state->camera = std::move(camera);
  return std::unique_ptr<LibcameraCamera>(new LibcameraCamera(std::move(state)));
}

LibcameraCamera::LibcameraCamera(std::shared_ptr<State> state) : state_(std::move(state)) {}

LibcameraCamera::~LibcameraCamera() { state_->shutdown(); }

Status LibcameraCamera::start() {
  State& s = *state_;
  if (s.started) return Ok{};
  if (auto c = s.configure(); !c) return c;
  if (auto m = s.map_buffers(); !m) return m;
  const libcamera::ControlList controls = s.start_controls();
  s.camera->requestCompleted.connect(state_.get(), &State::on_complete);
  s.camera->disconnected.connect(state_.get(), &State::on_disconnected);
  s.running.store(true);
  if (const int err = s.camera->start(&controls); err < 0) {
    s.running.store(false);
    s.camera->requestCompleted.disconnect(state_.get());
    s.camera->disconnected.disconnect(state_.get());
    return Error{fmt::format("{}: cannot start: {}", s.name, std::strerror(-err))};
  }
  s.started = true;
  for (auto& request : s.requests)
    if (const int err = s.camera->queueRequest(request.get()); err < 0)
      return Error{fmt::format("{}: cannot queue a request: {}", s.name, std::strerror(-err))};
  spdlog::info("{}: libcamera {} at {} fps, {} buffers", s.name, describe(s.format), s.fps, s.requests.size());
  return Ok{};
}

std::optional<Frame> LibcameraCamera::next(std::chrono::milliseconds timeout) {
  State& s = *state_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    libcamera::Request* request = nullptr;
    {
      std::unique_lock lock(s.mutex);
      auto ready = [&] { return s.stopped || !s.completed.empty(); };
      if (timeout.count() < 0)
        s.ready.wait(lock, ready);
      else if (!s.ready.wait_until(lock, deadline, ready))
        return std::nullopt;
      if (s.stopped) return std::nullopt;
      request = s.completed.front();
      s.completed.pop_front();
    }
    const libcamera::FrameBuffer* buffer = request->findBuffer(s.stream);
    const libcamera::FrameMetadata& meta = buffer->metadata();
    if (meta.status != libcamera::FrameMetadata::FrameSuccess || meta.planes().empty() ||
        meta.planes()[0].bytesused < s.format.min_bytesperline() * s.format.height) {
      ++s.dropped_error;
      s.requeue(request);
      continue;
    }
    if (s.last_sequence && meta.sequence > *s.last_sequence + 1) s.dropped_gap += meta.sequence - *s.last_sequence - 1;
    s.last_sequence = meta.sequence;
    // SensorTimestamp: start of exposure, CLOCK_MONOTONIC, ns; the buffer's own time otherwise.
    const auto t = request->metadata().get(libcamera::controls::SensorTimestamp);
    const FrameInfo info{meta.sequence, t ? *t : static_cast<std::int64_t>(meta.timestamp)};
    auto lease = std::make_shared<const RequestLease>(state_, request);
    ++s.frames;
    return Frame(s.format, info, lease, {s.mappings.at(buffer)->data() + buffer->planes()[0].offset, s.format.frame_bytes()});
  }
}

void LibcameraCamera::stop() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stopped = true;
    state_->completed.clear();
  }
  state_->ready.notify_all();
}

CameraCounters LibcameraCamera::counters() const {
  CameraCounters c;
  c.frames = state_->frames.load();
  c.dropped_error = state_->dropped_error.load();
  c.dropped_gap = state_->dropped_gap.load();
  c.losses = state_->losses.load();
  return c;
}

FrameFormat LibcameraCamera::format() const { return state_->format; }
double LibcameraCamera::fps() const { return state_->fps; }
const std::string& LibcameraCamera::name() const { return state_->name; }

}  // namespace spinewatch

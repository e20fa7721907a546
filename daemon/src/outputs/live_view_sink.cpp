#include "outputs/sinks.hpp"

namespace spinewatch {

LiveViewSink::LiveViewSink(const CameraRig& rig, LiveViewOptions view)
    // The render thread hands each picture to the server; it draws only
    // while a viewer of the server wants pictures, so never before start().
    : live_(std::make_unique<LiveView>(rig, std::move(view), [this](std::shared_ptr<const LiveFrame> frame) {
        if (http_) http_->on_frame(std::move(frame));
      })) {}

Status LiveViewSink::start(boost::asio::io_context& io, const HttpOptions& options, HttpHandlers handlers,
                           StationInfo station) {
  auto server = HttpServer::start(io, options, std::move(handlers), std::move(station), *live_);
  if (!server) return server.error();
  http_ = std::move(server).value();
  return Ok{};
}

}  // namespace spinewatch

#include "spinewatch/sync/trigger_controller.hpp"

#include <fmt/format.h>

#include "controller/serial_line.hpp"

namespace spinewatch::sync {

namespace {
constexpr unsigned kBaud = 115200;
}

TriggerController::TriggerController(std::string device, std::unique_ptr<SerialLine> line, Options options)
    : device_(std::move(device)), line_(std::move(line)), options_(options) {}

TriggerController::~TriggerController() = default;

Error TriggerController::failure(std::string_view request, std::string_view problem) const {
  return Error{fmt::format("trigger controller {}: {}: {}", device_, request, problem)};
}

Result<std::unique_ptr<TriggerController>> TriggerController::open(const std::string& device, Options options) {
  auto line = SerialLine::open(device, kBaud);
  if (!line) return Error{fmt::format("trigger controller {}: {}", device, line.error().message)};
  std::unique_ptr<TriggerController> controller(new TriggerController(device, std::move(line).value(), options));

  // Ask until the (possibly rebooting) controller answers or boot_wait ends.
  const auto deadline = std::chrono::steady_clock::now() + options.boot_wait;
  for (;;) {
    auto v = controller->version();
    if (v) return controller;
    const bool silent = v.error().message.find("no reply") != std::string::npos;
    if (!silent || std::chrono::steady_clock::now() >= deadline) return v.error();
  }
}

Result<std::string> TriggerController::request(std::string_view line) {
  line_->discard_input();
  if (auto written = line_->write_line(line, options_.reply_timeout); !written)
    return failure(line, written.error().message);
  for (;;) {
    auto reply = line_->read_line(options_.reply_timeout);
    if (!reply) return failure(line, reply.error().message);
    if (!reply->has_value())
      return failure(line, fmt::format("no reply within {} ms (is it a spinewatch trigger controller at 115200 baud?)",
                                       options_.reply_timeout.count()));
    const std::string& text = **reply;
    if (text.empty()) continue;  // a bare line end, e.g. from the boot
    if (text == "OK") return std::string{};
    if (text.rfind("OK ", 0) == 0) return text.substr(3);
    if (text.rfind("ERR ", 0) == 0) return failure(line, text.substr(4));
    return failure(line, fmt::format("unexpected reply '{}'", text));
  }
}

Result<TriggerControllerVersion> TriggerController::version() {
  auto text = request("VERSION");
  if (!text) return text.error();
  auto v = parse_trigger_version("OK " + *text);
  if (!v) return failure("VERSION", v.error().message);
  if (v->protocol != kTriggerProtocolVersion)
    return failure("VERSION", fmt::format("firmware {} speaks protocol {}, spinewatch speaks {}; flash the matching "
                                          "firmware (docs/hardware.md)",
                                          v->firmware, v->protocol, kTriggerProtocolVersion));
  return v;
}

Status TriggerController::configure(const TriggerSettings& s) {
  auto r = request(fmt::format("CONFIG {:.3f} {} {} {}", s.rate_hz, s.width_us, s.delay_a_us, s.delay_b_us));
  if (!r) return r.error();
  return Ok{};
}

Status TriggerController::start() {
  auto r = request("START");
  if (!r) return r.error();
  return Ok{};
}

Status TriggerController::stop() {
  auto r = request("STOP");
  if (!r) return r.error();
  return Ok{};
}

Result<TriggerControllerStatus> TriggerController::status() {
  auto text = request("STATUS");
  if (!text) return text.error();
  auto s = parse_trigger_status("OK " + *text);
  if (!s) return failure("STATUS", s.error().message);
  return s;
}

}  // namespace spinewatch::sync

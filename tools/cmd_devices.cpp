// spinewatch devices: what an installer needs to fill in the configuration,
// the V4L2 capture nodes with their formats and sizes, the libcamera
// cameras (when built with libcamera), and the GPIO chips with their lines.
#include <cstdio>
#include <exception>
#include <memory>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gpiod.hpp>

#include "command.hpp"
#include "spinewatch/capture/libcamera_camera.hpp"
#include "spinewatch/capture/v4l2_probe.hpp"

namespace spinewatch::cli {
namespace {

void list_video_devices() {
  const auto nodes = list_video_nodes();
  if (nodes.empty()) {
    fmt::print("No V4L2 video devices (/dev/video*) found.\n");
    return;
  }
  fmt::print("V4L2 video devices:\n");
  auto device = system_v4l2_device();
  for (const auto& path : nodes) {
    auto info = probe_v4l2_device(*device, path);
    if (!info) {
      fmt::print("  {}: {}\n", path, info.error().message);
      continue;
    }
    fmt::print("  {}: {} (driver {}, bus {})\n", path, info->card, info->driver, info->bus);
    if (!info->capture) {
      fmt::print("    not a video capture node (metadata or output); not usable as a camera\n");
      continue;
    }
    if (!info->streaming) fmt::print("    no streaming I/O: not usable as a camera\n");
    for (const auto& f : info->formats) {
      fmt::print("    {} ({}): {}\n", f.fourcc, f.description, f.sizes.empty() ? "no sizes listed" : fmt::format("{}", fmt::join(f.sizes, " ")));
    }
  }
}

// With libcamera built: the cameras it sees, by the ids cameras.frontal
// and cameras.lateral take when cameras.source = "libcamera".
void list_libcamera_cameras_found() {
  if (!libcamera_built()) return;
  auto cameras = list_libcamera_cameras();
  if (!cameras) {
    fmt::print("libcamera: {}\n", cameras.error().message);
    return;
  }
  if (cameras->empty()) {
    fmt::print("No libcamera cameras found.\n");
    return;
  }
  fmt::print("libcamera cameras (cameras.source = \"libcamera\"; use the id in quotes):\n");
  for (const auto& c : *cameras) {
    fmt::print("  \"{}\"{}\n", c.id, c.model.empty() ? std::string() : fmt::format(": {}", c.model));
    for (const auto& f : c.formats) fmt::print("    {}\n", f);
  }
}

void list_gpio_chips() {
  int chips = 0;
  try {
    for (auto& chip : gpiod::make_chip_iter()) {
      if (chips++ == 0) fmt::print("GPIO chips:\n");
      fmt::print("  {} [{}]: {} lines\n", chip.name(), chip.label(), chip.num_lines());
      for (unsigned i = 0; i < chip.num_lines(); ++i) {
        const auto line = chip.get_line(i);
        const std::string name = line.name();
        const std::string consumer = line.consumer();
        fmt::print("    line {:>3}: {:<16} {}{}\n", i, name.empty() ? "unnamed" : fmt::format("\"{}\"", name),
                   line.is_used() ? "used by " : "unused",
                   line.is_used() ? (consumer.empty() ? std::string("the kernel") : consumer) : std::string());
      }
    }
  } catch (const std::exception& e) {
    fmt::print("  GPIO: {}\n", e.what());
  }
  if (chips == 0) fmt::print("No GPIO chips (/dev/gpiochip*) found.\n");
}

}  // namespace

void add_devices_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand("devices", "List V4L2 cameras and GPIO chips for the configuration");
  cmd->callback([&exit_code] {
    list_video_devices();
    list_libcamera_cameras_found();
    list_gpio_chips();
    std::fflush(stdout);
    exit_code.value = 0;
  });
}

}  // namespace spinewatch::cli

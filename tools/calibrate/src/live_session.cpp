#include "spinewatch/calibrate/live_session.hpp"

#include "spinewatch/calibrate/grey_image.hpp"

#include <optional>

#include <fmt/format.h>

namespace spinewatch {
namespace {

constexpr const char* kNames[2] = {"frontal", "lateral"};

// Runs one phase: frames from both cameras into their collectors until each
// has `target[i]`, printing progress as the counts change.
Status run_phase(std::array<Camera*, 2> cameras, std::array<ViewCollector, 2>& collectors, std::array<int, 2> target,
                 const char* what, const LiveSessionOptions& options, const LiveSessionHooks& hooks,
                 std::optional<cv::Size>& size) {
  const auto deadline = std::chrono::steady_clock::now() + options.timeout;
  std::array<int, 2> shown = {-1, -1};
  auto done = [&] { return collectors[0].kept() >= target[0] && collectors[1].kept() >= target[1]; };
  while (true) {
    const std::array<int, 2> now = {collectors[0].kept(), collectors[1].kept()};
    if (now != shown && hooks.progress) {
      std::string line;
      for (int i = 0; i < 2; ++i)
        if (target[i] > 0)
          line += fmt::format("{}{}: {}/{} {}", line.empty() ? "" : ", ", kNames[i], std::min(now[i], target[i]),
                              target[i], line.empty() ? what : "");
      // "frontal: 7/12 views, lateral: 5/12"
      while (!line.empty() && line.back() == ' ') line.pop_back();
      hooks.progress(line);
    }
    shown = now;
    if (done()) return Ok{};
    if (std::chrono::steady_clock::now() > deadline) {
      std::string seen;
      for (int i = 0; i < 2; ++i)
        if (target[i] > 0)
          seen += fmt::format("{}{}: {}/{} {} ({})", seen.empty() ? "" : "; ", kNames[i],
                              std::min(collectors[i].kept(), target[i]), target[i], what, collectors[i].summary());
      return Error{fmt::format("calibrate --live: the {} were not complete after {} s — {}. A view is kept when the "
                               "board is found with enough corners, held still, at a pose not kept before",
                               what, std::chrono::duration_cast<std::chrono::seconds>(options.timeout).count(), seen)};
    }
    for (int i = 0; i < 2; ++i) {
      auto frame = cameras[i]->next(std::chrono::milliseconds(100));
      if (!frame) continue;
      const cv::Mat grey = grey_image(*frame);
      if (!size) size = grey.size();
      if (grey.size() != *size)
        return Error{fmt::format("calibrate --live: the {} camera's frames are {}x{}, the other's {}x{}", kNames[i],
                                 grey.cols, grey.rows, size->width, size->height)};
      // A camera that has all it needs still streams (its buffers must be
      // returned); its frames are not looked at.
      if (collectors[i].kept() < target[i]) collectors[i].offer(grey);
    }
  }
}

}  // namespace

Result<LiveSession> collect_live(std::array<Camera*, 2> cameras, const CalibrationBoard& board,
                                 const LiveSessionOptions& options, const LiveSessionHooks& hooks) {
  std::optional<cv::Size> size;
  std::array<ViewCollector, 2> views = {ViewCollector(board, options.collector),
                                        ViewCollector(board, options.collector)};
  const std::array<int, 2> wanted = {options.need_views[0] ? options.views : 0,
                                     options.need_views[1] ? options.views : 0};
  if (wanted[0] + wanted[1] > 0)
    if (auto s = run_phase(cameras, views, wanted, "views", options, hooks, size); !s) return s.error();
  if (hooks.before_placement) hooks.before_placement();
  ViewCollectorOptions still = options.collector;
  still.distinct_px = 0;  // the board lies still: every still frame counts
  std::array<ViewCollector, 2> placed = {ViewCollector(board, still), ViewCollector(board, still)};
  if (auto s = run_phase(cameras, placed, {options.placement_frames, options.placement_frames}, "placement frames",
                         options, hooks, size);
      !s)
    return s.error();
  LiveSession out;
  out.size = *size;
  for (int i = 0; i < 2; ++i) {
    out.frames[i].views = views[i].frames();
    out.frames[i].placement = placed[i].frames();
    // Each camera keeps its own still frames: view i of one is not view i
    // of the other (the placement board lies still, so its frames pair).
    out.frames[i].views_taken_together = false;
  }
  return out;
}

}  // namespace spinewatch

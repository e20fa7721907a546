#pragma once
// Replay overlays (spinewatch replay --overlay): the drawing of
// spinewatch/overlay/overlay.hpp over the recording's own frames, one PNG
// per N-th pair.
#include <cstdint>
#include <filesystem>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"
#include "spinewatch/overlay/overlay.hpp"
#include "spinewatch/replay/replay.hpp"

namespace spinewatch {

// The overlay of one replayed pair, over its camera pixels.
cv::Mat render_overlay(const ReplayedPair& pair, const OverlayOptions& options = {});

// Writes the overlay of every `every`-th pair (the first, then every N-th
// after it) as DIR/pair_<seq, 6 digits>.png.
class OverlayWriter {
 public:
  // Creates DIR; an error names DIR when it cannot be created or written.
  static Result<OverlayWriter> create(const std::filesystem::path& dir, std::uint64_t every,
                                      OverlayOptions options = {});

  Status write(const ReplayedPair& pair);
  std::uint64_t written() const { return written_; }

 private:
  OverlayWriter(std::filesystem::path dir, std::uint64_t every, OverlayOptions options)
      : dir_(std::move(dir)), every_(every), options_(options) {}
  std::filesystem::path dir_;
  std::uint64_t every_ = 1;
  OverlayOptions options_;
  std::uint64_t seen_ = 0, written_ = 0;
};

}  // namespace spinewatch

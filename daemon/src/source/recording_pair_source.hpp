#pragma once
// Frame pairs from a recording directory: RecordingSource (paced or fast,
// looping) through the same free-run pairer the cameras use.
#include <atomic>
#include <filesystem>
#include <memory>

#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct RecordingPairOptions {
  bool paced = true;  // at the recorded rate, timestamps on CLOCK_MONOTONIC
  bool loop = true;
};

Result<std::unique_ptr<PairSource>> open_recording_pair_source(const std::filesystem::path& dir,
                                                               RecordingPairOptions options);

}  // namespace spinewatch

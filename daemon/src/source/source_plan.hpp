#pragma once
// Which frames the daemon runs on (docs/interfaces.md §6, config [cameras]):
// the two cameras, a recording, or the embedded default — a phantom
// recording replayed in a loop — when no cameras are attached.
#include <filesystem>
#include <string>
#include <vector>

#include "spinewatch/daemon/config.hpp"

namespace spinewatch {

struct SourcePlan {
  enum class Kind { Cameras, Recording } kind = Kind::Recording;
  std::filesystem::path recording;  // Kind::Recording
  bool embedded = false;            // the recording is the embedded default
  bool paced = true;                // cameras.replay
  std::string why;                  // for the log: how the choice was made
};

// Where the embedded recording is looked for, in order: $SPINEWATCH_DATA_DIR/demo,
// the build tree's share/spinewatch/demo, the installed share/spinewatch/demo.
std::vector<std::filesystem::path> embedded_recording_dirs();
Result<SourcePlan> plan_source(const Config& config);

}  // namespace spinewatch

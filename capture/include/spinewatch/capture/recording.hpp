#pragma once
// Recording directories (docs/interfaces.md §2): frontal.raw + lateral.raw as
// v4l2-ctl --stream-mmap --stream-to=FILE writes them (whole frames, no
// headers), recording.json, calibration.yaml.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/frames/view.hpp"

namespace spinewatch {

// What recording.json says.
struct RecordingInfo {
  FrameFormat format;  // bytesperline = width × bpp unless "bytesperline" is given
  double fps = 30.0;
  // Per-frame metadata, one entry per frame actually in the .raw file after
  // validation; filled with seq = i, t_ns = i / fps when the JSON has none.
  std::vector<FrameInfo> frames[2];
  nlohmann::json subject;  // optional, null when absent
  std::string notes;       // optional
};

// Reads a recording directory. Opening validates everything and returns one
// error naming the file and the problem; a truncated last frame is dropped
// with a warning (warnings() lists them).
class RecordingReader {
 public:
  static Result<RecordingReader> open(const std::filesystem::path& dir);

  const RecordingInfo& info() const { return info_; }
  const std::filesystem::path& dir() const { return dir_; }
  std::size_t frame_count(View view) const { return info_.frames[static_cast<int>(view)].size(); }
  // Reads frame `index` of a view (a copy owned by the Frame). Not
  // thread-safe: one reader per thread. An index past the end, or a file
  // that shrank since open(), is an Error naming the file.
  Result<Frame> read(View view, std::size_t index);
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::filesystem::path dir_;
  RecordingInfo info_;
  std::unique_ptr<std::ifstream> streams_[2];
  std::vector<std::string> warnings_;
};

// Writes a recording directory in the same layout: frames appended to the
// .raw files as they come, recording.json (with per-frame seq and t_ns) at
// finish(); calibration.yaml is the caller's (save_calibration in the estimator).
class RecordingWriter {
 public:
  static Result<RecordingWriter> create(const std::filesystem::path& dir, FrameFormat format, double fps);

  // Appends a frame's bytes (frame.format() must equal the writer's format;
  // bytes beyond bytesperline × height, a driver's padding, are not written).
  Status write(View view, const Frame& frame);
  // `subject` and `notes` go into recording.json when not null/empty.
  // recording.json is still written when a stream got no frames, but the
  // result is then an Error (such a recording would not replay).
  Status finish(const nlohmann::json& subject = nullptr, const std::string& notes = {});

 private:
  std::filesystem::path dir_;
  RecordingInfo info_;
  std::unique_ptr<std::ofstream> streams_[2];
};

}  // namespace spinewatch

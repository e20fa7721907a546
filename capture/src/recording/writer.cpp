#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "recording_json.hpp"
#include "spinewatch/capture/recording.hpp"

namespace spinewatch {
namespace fs = std::filesystem;
using namespace recording_detail;

namespace {

fs::path raw_path(const fs::path& dir, View view) { return dir / fmt::format("{}.raw", to_string(view)); }

Error io_error(const fs::path& file, std::string_view what) {
  return Error{fmt::format("{}: {}: {}", file.string(), what, std::strerror(errno))};
}

Status check_format(const fs::path& dir, const FrameFormat& f, double fps) {
  const auto bad = [&](const std::string& problem) { return Error{dir.string() + ": cannot record " + problem}; };
  if (f.width < 1 || f.width > kMaxDimension || f.height < 1 || f.height > kMaxDimension)
    return bad(fmt::format("{}x{} frames (each side must be 1..{})", f.width, f.height, kMaxDimension));
  if (f.bytesperline < f.min_bytesperline() || f.bytesperline > kMaxBytesPerLine)
    return bad(fmt::format("{}: bytesperline must be at least {}", describe(f), f.min_bytesperline()));
  if (!(fps > 0.0 && fps <= kMaxFps)) return bad(fmt::format("at {} fps (must be > 0 and <= {})", fps, kMaxFps));
  return Ok{};
}

}  // namespace

Result<RecordingWriter> RecordingWriter::create(const fs::path& dir, FrameFormat format, double fps) {
  if (auto ok = check_format(dir, format, fps); !ok) return ok.error();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Error{fmt::format("{}: cannot create the directory: {}", dir.string(), ec.message())};
  // A recording.json left from an earlier recording would describe the wrong
  // frames until finish() replaces it.
  fs::remove(dir / "recording.json", ec);
  if (ec) return Error{fmt::format("{}: cannot remove the old recording.json: {}", dir.string(), ec.message())};

  RecordingWriter writer;
  writer.dir_ = dir;
  writer.info_.format = format;
  writer.info_.fps = fps;
  for (View view : kViews) {
    const auto raw = raw_path(dir, view);
    auto& out = writer.streams_[static_cast<int>(view)];
    out = std::make_unique<std::ofstream>(raw, std::ios::binary | std::ios::trunc);
    if (!*out) return io_error(raw, "cannot create");
  }
  return writer;
}

Status RecordingWriter::write(View view, const Frame& frame) {
  const int v = static_cast<int>(view);
  const auto raw = raw_path(dir_, view);
  auto& out = streams_[v];
  if (!out) return Error{raw.string() + ": cannot write a frame after finish()"};
  if (frame.format() != info_.format)
    return Error{fmt::format("{}: frame format {} differs from the recording's {}", raw.string(),
                             describe(frame.format()), describe(info_.format))};
  // Some drivers report a sizeimage beyond bytesperline × height; the file
  // holds exactly bytesperline × height a frame, so that tail is not written.
  const auto frame_bytes = info_.format.frame_bytes();
  if (frame.bytes().size() < frame_bytes)
    return Error{fmt::format("{}: frame of {} bytes, expected {} for {}", raw.string(), frame.bytes().size(),
                             frame_bytes, describe(info_.format))};
  auto& frames = info_.frames[v];
  if (!frames.empty()) {
    // recording.json must stay readable: the reader rejects these.
    if (frame.sequence() <= frames.back().sequence)
      return Error{fmt::format("{}: frame seq {} does not follow the previous {}", raw.string(), frame.sequence(),
                               frames.back().sequence)};
    if (frame.timestamp_ns() < frames.back().timestamp_ns)
      return Error{fmt::format("{}: frame t_ns {} is before the previous {}", raw.string(), frame.timestamp_ns(),
                               frames.back().timestamp_ns)};
  }
  out->write(reinterpret_cast<const char*>(frame.bytes().data()), static_cast<std::streamsize>(frame_bytes));
  if (!*out) return io_error(raw, "write failed");
  frames.push_back(frame.info());
  return Ok{};
}

Status RecordingWriter::finish(const nlohmann::json& subject, const std::string& notes) {
  for (View view : kViews) {
    auto& out = streams_[static_cast<int>(view)];
    if (!out) return Error{dir_.string() + ": finish() was already called"};
    out->close();
    if (!*out) return io_error(raw_path(dir_, view), "write failed on close");
    out.reset();
  }
  info_.subject = subject;
  info_.notes = notes;

  // Written beside and renamed, so a crash never leaves a half-written recording.json.
  const auto json_path = dir_ / "recording.json";
  const auto tmp_path = dir_ / "recording.json.tmp";
  {
    std::ofstream out(tmp_path, std::ios::binary | std::ios::trunc);
    out << format_recording_json(info_);
    out.close();
    if (!out) return io_error(tmp_path, "write failed");
  }
  std::error_code ec;
  fs::rename(tmp_path, json_path, ec);
  if (ec) return Error{fmt::format("{}: cannot rename to recording.json: {}", tmp_path.string(), ec.message())};

  for (View view : kViews)
    if (info_.frames[static_cast<int>(view)].empty())
      return Error{fmt::format("{}: recording written, but the {} stream is empty, so it will not replay",
                               dir_.string(), to_string(view))};
  return Ok{};
}

}  // namespace spinewatch

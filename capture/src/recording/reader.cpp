#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "raw_layout.hpp"
#include "recording_json.hpp"
#include "spinewatch/capture/recording.hpp"

namespace spinewatch {
namespace fs = std::filesystem;
using namespace recording_detail;

namespace {

std::string raw_name(View view) { return fmt::format("{}.raw", to_string(view)); }

Result<std::uintmax_t> raw_file_size(const fs::path& raw) {
  std::error_code ec;
  const auto status = fs::status(raw, ec);
  if (!fs::exists(status)) return Error{raw.string() + ": missing (the recording has no " + raw.filename().string() + ")"};
  if (!fs::is_regular_file(status)) return Error{raw.string() + ": not a regular file"};
  const auto size = fs::file_size(raw, ec);
  if (ec) return Error{raw.string() + ": cannot read its size: " + ec.message()};
  return size;
}

}  // namespace

Result<RecordingReader> RecordingReader::open(const fs::path& dir) {
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (!fs::exists(status)) return Error{dir.string() + ": no such recording directory"};
  if (!fs::is_directory(status)) return Error{dir.string() + ": not a directory (a recording is a directory)"};

  const auto json_path = dir / "recording.json";
  auto declared = parse_recording_json(json_path);
  if (!declared) return declared.error();

  RecordingReader reader;
  reader.dir_ = dir;
  reader.info_.format = declared->format;
  reader.info_.fps = declared->fps;
  reader.info_.subject = std::move(declared->subject);
  reader.info_.notes = std::move(declared->notes);

  for (View view : kViews) {
    const int v = static_cast<int>(view);
    const auto raw = dir / raw_name(view);
    auto size = raw_file_size(raw);
    if (!size) return size.error();

    auto& listed = declared->frames[v];
    const std::optional<std::size_t> listed_count =
        listed ? std::optional<std::size_t>(listed->size()) : std::nullopt;
    auto layout = fit_raw_file(raw, *size, reader.info_.format, listed_count,
                               fmt::format("{} frames.{}", json_path.string(), to_string(view)));
    if (!layout) return layout.error();
    if (layout->warning) reader.warnings_.push_back(*layout->warning);

    if (listed) {
      listed->resize(layout->frames);  // drops the entry of a truncated last frame
      reader.info_.frames[v] = std::move(*listed);
    } else {
      reader.info_.frames[v] = default_frame_infos(layout->frames, reader.info_.fps);
    }

    reader.streams_[v] = std::make_unique<std::ifstream>(raw, std::ios::binary);
    if (!*reader.streams_[v]) return Error{fmt::format("{}: cannot open: {}", raw.string(), std::strerror(errno))};
  }

  for (const auto& warning : reader.warnings_) spdlog::warn("{}", warning);
  return reader;
}

Result<Frame> RecordingReader::read(View view, std::size_t index) {
  const int v = static_cast<int>(view);
  const auto raw = dir_ / raw_name(view);
  const auto& frames = info_.frames[v];
  if (index >= frames.size())
    return Error{fmt::format("{}: frame {} is out of range (the stream has {} frames)", raw.string(), index,
                             frames.size())};
  const auto frame_bytes = info_.format.frame_bytes();
  std::vector<std::uint8_t> bytes(frame_bytes);
  auto& in = *streams_[v];
  in.clear();
  in.seekg(static_cast<std::streamoff>(index * frame_bytes));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(frame_bytes));
  if (!in || static_cast<std::size_t>(in.gcount()) != frame_bytes) {
    in.clear();
    return Error{fmt::format("{}: cannot read frame {} ({} bytes at offset {}): the file shrank or is unreadable",
                             raw.string(), index, frame_bytes, index * frame_bytes)};
  }
  return Frame::owning(info_.format, frames[index], std::move(bytes));
}

}  // namespace spinewatch

// The writer's side of recording.json, and the metadata a recording without
// "frames" implies.
#include <cmath>

#include <fmt/format.h>

#include "recording_json.hpp"

namespace spinewatch::recording_detail {

using nlohmann::json;

std::vector<FrameInfo> default_frame_infos(std::size_t count, double fps) {
  std::vector<FrameInfo> frames(count);
  for (std::size_t i = 0; i < count; ++i)
    frames[i] = {i, static_cast<std::int64_t>(std::llround(static_cast<double>(i) * 1e9 / fps))};
  return frames;
}

std::string format_recording_json(const RecordingInfo& info) {
  const auto& f = info.format;
  std::string out = "{\n";
  out += fmt::format("  \"pixel_format\": {},\n", json(std::string(to_string(f.pixel_format))).dump());
  out += fmt::format("  \"width\": {},\n  \"height\": {},\n", f.width, f.height);
  if (f.bytesperline != f.min_bytesperline()) out += fmt::format("  \"bytesperline\": {},\n", f.bytesperline);
  out += fmt::format("  \"fps\": {},\n", json(info.fps).dump());
  out += "  \"frames\": {";
  for (View view : kViews) {
    out += fmt::format("{}\n    \"{}\": [", view == View::Frontal ? "" : ",", to_string(view));
    const auto& frames = info.frames[static_cast<int>(view)];
    for (std::size_t i = 0; i < frames.size(); ++i)
      out += fmt::format("{}\n      {{\"seq\": {}, \"t_ns\": {}}}", i ? "," : "", frames[i].sequence,
                         frames[i].timestamp_ns);
    out += frames.empty() ? "]" : "\n    ]";
  }
  out += "\n  }";
  if (!info.subject.is_null()) out += ",\n  \"subject\": " + info.subject.dump();
  if (!info.notes.empty()) out += ",\n  \"notes\": " + json(info.notes).dump();
  out += "\n}\n";
  return out;
}

}  // namespace spinewatch::recording_detail

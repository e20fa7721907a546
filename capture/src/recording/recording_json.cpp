#include "recording_json.hpp"

#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "spinewatch/capture/json_text.hpp"
#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch::recording_detail {
namespace {

using nlohmann::json;

// Every problem becomes "<file>: <problem>", one line, naming the field.
class JsonChecker {
 public:
  explicit JsonChecker(const std::filesystem::path& file) : file_(file.string()) {}

  Error error(const std::string& problem) const { return Error{file_ + ": " + problem}; }

  static std::string describe(const json& value) {
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return fmt::format("{} ({})", text, value.type_name());
  }

  Result<std::int64_t> integer(const json& value, const std::string& field, std::int64_t min,
                               std::int64_t max) const {
    if (!value.is_number_integer())
      return error(fmt::format("\"{}\" must be an integer, got {}", field, describe(value)));
    if (value.is_number_unsigned() && value.get<std::uint64_t>() > static_cast<std::uint64_t>(max))
      return error(fmt::format("\"{}\" is out of range: {} (allowed {}..{})", field, value.dump(), min, max));
    const auto v = value.get<std::int64_t>();
    if (v < min || v > max)
      return error(fmt::format("\"{}\" is out of range: {} (allowed {}..{})", field, v, min, max));
    return v;
  }

  Result<PixelFormat> pixel_format(const json& value, const std::string& field) const {
    if (!value.is_string())
      return error(fmt::format("\"{}\" must be a string, got {}", field, describe(value)));
    const auto name = value.get<std::string>();
    if (auto format = parse_pixel_format(name)) return *format;
    return error(fmt::format("\"{}\": unknown pixel format \"{}\" (supported: YUYV, GREY)", field, printable(name)));
  }

 private:
  std::string file_;
};

// The optional format fields of one object (top level or a "streams" entry).
struct FormatFields {
  std::optional<PixelFormat> pixel_format;
  std::optional<std::uint32_t> width, height, bytesperline;
};

Result<FormatFields> read_format_fields(const JsonChecker& check, const json& object, const std::string& prefix) {
  FormatFields fields;
  if (auto it = object.find("pixel_format"); it != object.end()) {
    auto pf = check.pixel_format(*it, prefix + "pixel_format");
    if (!pf) return pf.error();
    fields.pixel_format = *pf;
  }
  for (auto [key, slot] : {std::pair{"width", &fields.width}, std::pair{"height", &fields.height}}) {
    if (auto it = object.find(key); it != object.end()) {
      auto v = check.integer(*it, prefix + key, 1, kMaxDimension);
      if (!v) return v.error();
      *slot = static_cast<std::uint32_t>(*v);
    }
  }
  if (auto it = object.find("bytesperline"); it != object.end()) {
    auto v = check.integer(*it, prefix + "bytesperline", 1, kMaxBytesPerLine);
    if (!v) return v.error();
    fields.bytesperline = static_cast<std::uint32_t>(*v);
  }
  return fields;
}

// Top-level fields overridden by a stream's own, then checked as a whole.
Result<FrameFormat> resolve_format(const JsonChecker& check, const FormatFields& top, const FormatFields& own,
                                   const std::string& prefix) {
  FrameFormat f;
  f.pixel_format = own.pixel_format.value_or(*top.pixel_format);
  f.width = own.width.value_or(*top.width);
  f.height = own.height.value_or(*top.height);
  const auto explicit_bpl = own.bytesperline ? own.bytesperline : top.bytesperline;
  f.bytesperline = explicit_bpl.value_or(f.min_bytesperline());
  if (f.bytesperline < f.min_bytesperline())
    return check.error(fmt::format("\"{}bytesperline\" is out of range: {} is less than width x bytes per pixel = {} ({} {}x{})",
                                   own.bytesperline ? prefix : "", f.bytesperline, f.min_bytesperline(),
                                   to_string(f.pixel_format), f.width, f.height));
  return f;
}

Result<View> view_named(const JsonChecker& check, const std::string& name, const std::string& where) {
  if (name == "frontal") return View::Frontal;
  if (name == "lateral") return View::Lateral;
  return check.error(fmt::format("\"{}\": unknown stream \"{}\" (expected frontal, lateral)", where, printable(name)));
}

Result<FrameFormat> read_format(const JsonChecker& check, const json& doc) {
  for (const char* key : {"pixel_format", "width", "height"})
    if (!doc.contains(key)) return check.error(fmt::format("missing required field \"{}\"", key));
  auto top = read_format_fields(check, doc, "");
  if (!top) return top.error();

  auto base = resolve_format(check, *top, {}, "");
  auto streams = doc.find("streams");
  if (streams == doc.end()) return base;
  if (!streams->is_object())
    return check.error(fmt::format("\"streams\" must be an object, got {}", JsonChecker::describe(*streams)));

  std::optional<FrameFormat> formats[2];
  for (auto it = streams->begin(); it != streams->end(); ++it) {
    auto view = view_named(check, it.key(), "streams");
    if (!view) return view.error();
    const std::string prefix = "streams." + it.key() + ".";
    if (!it->is_object())
      return check.error(fmt::format("\"streams.{}\" must be an object, got {}", it.key(), JsonChecker::describe(*it)));
    auto own = read_format_fields(check, *it, prefix);
    if (!own) return own.error();
    auto format = resolve_format(check, *top, *own, prefix);
    if (!format) return format.error();
    formats[static_cast<int>(*view)] = *format;
  }
  for (auto& f : formats) {
    if (f) continue;
    if (!base) return base.error();
    f = *base;
  }
  if (*formats[0] != *formats[1])
    return check.error(fmt::format("streams whose formats differ: frontal is {}, lateral is {} "
                                   "(both cameras must deliver the same format)",
                                   describe(*formats[0]), describe(*formats[1])));
  return *formats[0];
}

Result<std::vector<FrameInfo>> read_frame_list(const JsonChecker& check, const json& list, const std::string& field) {
  if (!list.is_array())
    return check.error(fmt::format("\"{}\" must be an array, got {}", field, JsonChecker::describe(list)));
  std::vector<FrameInfo> frames;
  frames.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& entry = list[i];
    const std::string where = fmt::format("{}[{}]", field, i);
    if (!entry.is_object())
      return check.error(fmt::format("\"{}\" must be an object {{\"seq\": n, \"t_ns\": t}}, got {}", where,
                                     JsonChecker::describe(entry)));
    for (const char* key : {"seq", "t_ns"})
      if (!entry.contains(key)) return check.error(fmt::format("\"{}\": missing field \"{}\"", where, key));
    auto seq = check.integer(entry["seq"], where + ".seq", 0, std::numeric_limits<std::int64_t>::max());
    if (!seq) return seq.error();
    auto t = check.integer(entry["t_ns"], where + ".t_ns", std::numeric_limits<std::int64_t>::min(),
                           std::numeric_limits<std::int64_t>::max());
    if (!t) return t.error();
    FrameInfo info{static_cast<std::uint64_t>(*seq), *t};
    if (!frames.empty()) {
      const auto& prev = frames.back();
      if (info.sequence <= prev.sequence)
        return check.error(fmt::format("\"{}.seq\" is {}, not greater than the previous frame's {} "
                                       "(seq must increase strictly)", where, info.sequence, prev.sequence));
      if (info.timestamp_ns < prev.timestamp_ns)
        return check.error(fmt::format("\"{}.t_ns\" is {}, less than the previous frame's {} "
                                       "(timestamps must not decrease)", where, info.timestamp_ns, prev.timestamp_ns));
    }
    frames.push_back(info);
  }
  return frames;
}

Result<json> parse_text(const JsonChecker& check, const std::string& text) {
  auto parsed = parse_json_text(text);
  if (!parsed) return check.error(fmt::format("invalid JSON: {}", parsed.error().message));
  return parsed;
}

}  // namespace

Result<DeclaredRecording> parse_recording_json(const std::filesystem::path& file) {
  const JsonChecker check(file);
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    return check.error("missing (a recording directory holds frontal.raw, lateral.raw and recording.json)");
  auto text = read_text_file(file);
  if (!text) return text.error();

  auto doc = parse_text(check, *text);
  if (!doc) return doc.error();
  if (!doc->is_object()) return check.error(fmt::format("must be a JSON object, got {}", JsonChecker::describe(*doc)));

  DeclaredRecording out;
  auto format = read_format(check, *doc);
  if (!format) return format.error();
  out.format = *format;

  const auto fps = doc->find("fps");
  if (fps == doc->end()) return check.error("missing required field \"fps\"");
  if (!fps->is_number())
    return check.error(fmt::format("\"fps\" must be a number, got {}", JsonChecker::describe(*fps)));
  out.fps = fps->get<double>();
  if (!(out.fps > 0.0 && out.fps <= kMaxFps))
    return check.error(fmt::format("\"fps\" is out of range: {} (must be > 0 and <= {})", fps->dump(), kMaxFps));

  if (auto frames = doc->find("frames"); frames != doc->end()) {
    if (!frames->is_object())
      return check.error(fmt::format("\"frames\" must be an object {{\"frontal\": [...], \"lateral\": [...]}}, got {}",
                                     JsonChecker::describe(*frames)));
    for (auto it = frames->begin(); it != frames->end(); ++it) {
      auto view = view_named(check, it.key(), "frames");
      if (!view) return view.error();
      auto list = read_frame_list(check, *it, "frames." + it.key());
      if (!list) return list.error();
      out.frames[static_cast<int>(*view)] = std::move(*list);
    }
  }

  if (auto subject = doc->find("subject"); subject != doc->end()) out.subject = *subject;
  if (auto notes = doc->find("notes"); notes != doc->end()) {
    if (!notes->is_string())
      return check.error(fmt::format("\"notes\" must be a string, got {}", JsonChecker::describe(*notes)));
    out.notes = notes->get<std::string>();
  }
  return out;
}

}  // namespace spinewatch::recording_detail

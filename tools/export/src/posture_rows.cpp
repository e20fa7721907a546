#include "spinewatch/export/posture_rows.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch::exporting {

Result<std::vector<SourceLine>> read_ndjson_lines(const std::filesystem::path& path) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  std::vector<SourceLine> lines;
  std::size_t start = 0, number = 0;
  while (start < text->size()) {
    std::size_t end = text->find('\n', start);
    if (end == std::string::npos) end = text->size();
    ++number;
    std::string line = text->substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") != std::string::npos)
      lines.push_back({std::move(line), fmt::format("{}:{}", path.string(), number), std::nullopt});
    start = end + 1;
  }
  return lines;
}

namespace {

Result<bool> within(const TimeRange::Bound& b, const SourceLine& line, std::int64_t t_ns, bool is_from) {
  std::int64_t t = t_ns;
  if (b.utc) {
    if (!line.stored_utc_ns)
      return Error{fmt::format("{}: a UTC bound, but posture lines carry no UTC time; give --from/--to in seconds of "
                               "the stream's clock (t_ns / 1e9)",
                               line.where)};
    t = *line.stored_utc_ns;
  }
  return is_from ? t >= b.ns : t < b.ns;
}

}  // namespace

Result<RowsRead> select_rows(const std::vector<SourceLine>& lines, const TimeRange& range) {
  RowsRead out;
  for (const SourceLine& line : lines) {
    nlohmann::json j = nlohmann::json::parse(line.text, nullptr, false);
    if (j.is_discarded()) return Error{fmt::format("{}: not JSON", line.where)};
    if (!j.is_object()) return Error{fmt::format("{}: not a JSON object", line.where)};
    // Lines without a class are postures (ground truth); other classes are skipped.
    if (auto c = j.find("class"); c != j.end() && *c != "posture") continue;
    auto posture = posture_from_json(j, line.where);
    if (!posture) return posture.error();
    bool in = true;
    for (auto [bound, is_from] : {std::pair{&range.from, true}, std::pair{&range.to, false}}) {
      if (!*bound) continue;
      auto w = within(**bound, line, posture->t_ns, is_from);
      if (!w) return w.error();
      in = in && *w;
    }
    if (!in) continue;
    ++out.postures;
    if (posture->state != TrackingState::Tracking || !posture->vertebrae) {
      ++out.omitted;
      continue;
    }
    if (!out.rows.empty() && posture->t_ns <= out.rows.back().t_ns)
      return Error{fmt::format("{}: t_ns {} does not follow the previous posture's {} (two streams in one file? "
                               "export one with --from/--to)",
                               line.where, posture->t_ns, out.rows.back().t_ns)};
    out.rows.push_back({posture->seq, posture->t_ns, *posture->vertebrae});
  }
  return out;
}

}  // namespace spinewatch::exporting

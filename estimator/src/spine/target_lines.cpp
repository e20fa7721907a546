#include "spinewatch/estimator/spine/target_lines.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace spinewatch {
namespace {

using nlohmann::json;

Result<Eigen::Vector3d> vec3(const json& line, const char* key, std::string_view where, bool unit) {
  auto it = line.find(key);
  if (it == line.end()) return Error{fmt::format("{}: {}: missing", where, key)};
  if (!it->is_array() || it->size() != 3) return Error{fmt::format("{}: {}: expected an array of 3 numbers", where, key)};
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!(*it)[i].is_number()) return Error{fmt::format("{}: {}[{}]: not a number", where, key, i)};
    v[int(i)] = (*it)[i].get<double>();
  }
  if (!v.allFinite()) return Error{fmt::format("{}: {}: not finite", where, key)};
  if (unit && std::abs(v.norm() - 1.0) > 0.05)
    return Error{fmt::format("{}: {}: not a unit vector (norm {:.3f})", where, key, v.norm())};
  return unit ? Eigen::Vector3d(v.normalized()) : v;
}

}  // namespace

Result<TargetLine> parse_target_line(std::string_view text, std::string_view where, std::uint64_t index) {
  json line = json::parse(text, nullptr, false);
  if (line.is_discarded()) return Error{fmt::format("{}: not valid JSON", where)};
  if (!line.is_object()) return Error{fmt::format("{}: expected a JSON object", where)};
  TargetLine t;
  auto neck = vec3(line, "neck", where, false);
  if (!neck) return neck.error();
  auto waist = vec3(line, "waist", where, false);
  if (!waist) return waist.error();
  t.targets.neck = *neck;
  t.targets.waist = *waist;
  for (auto [key, out] : {std::pair{"neck_dir", &t.targets.neck_dir}, std::pair{"waist_dir", &t.targets.waist_dir}}) {
    if (!line.contains(key) || line[key].is_null()) continue;
    auto d = vec3(line, key, where, true);
    if (!d) return d.error();
    *out = *d;
  }
  t.seq = index;
  if (auto it = line.find("seq"); it != line.end()) {
    if (!it->is_number_unsigned()) return Error{fmt::format("{}: seq: not a non-negative integer", where)};
    t.seq = it->get<std::uint64_t>();
  }
  if (auto it = line.find("t_ns"); it != line.end()) {
    if (!it->is_number_integer()) return Error{fmt::format("{}: t_ns: not an integer", where)};
    t.t_ns = it->get<std::int64_t>();
  }
  return t;
}

Result<std::vector<TargetLine>> parse_target_lines(std::string_view text, std::string_view name) {
  std::vector<TargetLine> lines;
  std::uint64_t number = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    auto t = parse_target_line(line, fmt::format("{}:{}", name, number), lines.size());
    if (!t) return t.error();
    lines.push_back(*t);
  }
  if (lines.empty()) return Error{fmt::format("{}: no target lines", name)};
  return lines;
}

}  // namespace spinewatch

#include "spinewatch/estimator/spine/subject.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {
namespace {
using nlohmann::json;

Result<double> positive(const json& v, std::string_view source, const std::string& field) {
  auto it = v.find(field.substr(field.rfind('.') + 1));
  if (it == v.end()) return Error{fmt::format("{}: {}: missing", source, field)};
  if (!it->is_number()) return Error{fmt::format("{}: {}: expected a number", source, field)};
  const double x = it->get<double>();
  if (!(x > 0 && x < 200)) return Error{fmt::format("{}: {}: {} is out of range (0, 200) mm", source, field, x)};
  return x;
}

Status numbers(const json& v, std::string_view source, const std::string& field, std::size_t n, double* out) {
  if (!v.is_array() || v.size() != n)
    return Error{fmt::format("{}: {}: expected an array of {} numbers", source, field, n)};
  for (std::size_t i = 0; i < n; ++i) {
    if (!v[i].is_number()) return Error{fmt::format("{}: {}[{}]: not a number", source, field, i)};
    out[i] = v[i].get<double>();
    if (!std::isfinite(out[i])) return Error{fmt::format("{}: {}[{}]: not finite", source, field, i)};
  }
  return Ok{};
}

}  // namespace

Result<SubjectSpine> parse_subject_json(std::string_view text, std::string_view source) {
  json root = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) return Error{fmt::format("{}: not valid JSON", source)};
  if (!root.is_object()) return Error{fmt::format("{}: expected a JSON object", source)};
  auto list = root.find("vertebrae");
  if (list == root.end()) return Error{fmt::format("{}: vertebrae: missing", source)};
  if (!list->is_array() || list->size() != kVertebraCount)
    return Error{fmt::format("{}: vertebrae: expected an array of {} entries T1…L5", source, kVertebraCount)};
  SubjectSpine subject;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const json& v = (*list)[i];
    const std::string ctx = fmt::format("vertebrae[{}]", i);
    if (!v.is_object()) return Error{fmt::format("{}: {}: expected an object", source, ctx)};
    auto name = v.find("name");
    if (name == v.end() || !name->is_string() || name->get<std::string>() != kVertebraNames[i])
      return Error{fmt::format("{}: {}.name: expected \"{}\"", source, ctx, kVertebraNames[i])};
    SubjectVertebra& out = subject[i];
    auto centre = v.find("body_center");
    if (centre == v.end()) return Error{fmt::format("{}: {}.body_center: missing", source, ctx)};
    if (auto s = numbers(*centre, source, ctx + ".body_center", 3, out.pose.body_center.data()); !s) return s.error();
    auto q = v.find("q");
    if (q == v.end()) return Error{fmt::format("{}: {}.q: missing", source, ctx)};
    double c[4];
    if (auto s = numbers(*q, source, ctx + ".q", 4, c); !s) return s.error();
    out.pose.q = Eigen::Quaterniond(c[0], c[1], c[2], c[3]);
    if (std::abs(out.pose.q.norm() - 1.0) > 1e-3)
      return Error{fmt::format("{}: {}.q: not a unit quaternion (norm {:.4f})", source, ctx, out.pose.q.norm())};
    out.pose.q.normalize();
    for (auto [key, field] : {std::pair{"height_mm", &out.dims.height_mm}, std::pair{"width_mm", &out.dims.width_mm},
                              std::pair{"depth_mm", &out.dims.depth_mm}}) {
      auto x = positive(v, source, ctx + "." + key);
      if (!x) return x.error();
      *field = *x;
    }
  }
  for (std::size_t i = 0; i + 1 < kVertebraCount; ++i) {
    const double gap = (subject[i].pose.body_center - subject[i + 1].pose.body_center).norm();
    if (gap < 5.0)
      return Error{fmt::format("{}: vertebrae[{}].body_center: {:.1f} mm from {}; expected distinct levels", source,
                               i, gap, kVertebraNames[i + 1])};
  }
  return subject;
}

Result<SubjectSpine> load_subject_file(const std::filesystem::path& path) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_subject_json(*text, path.string());
}

std::string subject_to_json(const SubjectSpine& subject) {
  json list = json::array();
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const auto& v = subject[i];
    list.push_back({{"name", kVertebraNames[i]},
                    {"body_center", {v.pose.body_center.x(), v.pose.body_center.y(), v.pose.body_center.z()}},
                    {"q", {v.pose.q.w(), v.pose.q.x(), v.pose.q.y(), v.pose.q.z()}},
                    {"height_mm", v.dims.height_mm},
                    {"width_mm", v.dims.width_mm},
                    {"depth_mm", v.dims.depth_mm}});
  }
  return json{{"vertebrae", std::move(list)}}.dump(1);
}

SubjectSpine generic_subject(double height_mm) {
  return subject_of_neutral(neutral_pose(generic_spine_spec(), height_mm), height_mm);
}

SubjectSpine subject_of_neutral(const SpinePose& neutral, double height_mm, const SpineSpec& spec) {
  const double s = size_scale(spec, height_mm);
  SubjectSpine subject;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    subject[i].pose = neutral[i];
    subject[i].dims = {spec.vertebrae[i].height_mm * s, spec.vertebrae[i].width_mm * s, spec.vertebrae[i].depth_mm * s};
  }
  return subject;
}

SpinePose neutral_of(const SubjectSpine& subject) {
  SpinePose pose;
  for (std::size_t i = 0; i < kVertebraCount; ++i) pose[i] = subject[i].pose;
  return pose;
}

}  // namespace spinewatch

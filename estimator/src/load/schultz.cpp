#include "spinewatch/estimator/load/schultz.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/toml_fields.hpp"
#include "spinewatch/estimator/units.hpp"

namespace spinewatch {
namespace {

Result<Eigen::Vector3d> vector3(const toml::table& t, std::string_view key, std::string_view source) {
  const toml::array* a = t[key].as_array();
  if (!a || a->size() != 3)
    return Error{fmt::format("{}:{}: geometry.{}: expected an array of 3 numbers", source, t.source().begin.line, key)};
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    auto x = (*a)[i].value<double>();
    if (!x) return Error{fmt::format("{}:{}: geometry.{}[{}]: not a number", source, a->source().begin.line, key, i)};
    v[int(i)] = *x;
  }
  return v;
}

// Spacing-weighted share of vertebra k within its region (thorax T1–T12, abdomen L1–L5).
double slice_share(const SpinePose& pose, std::size_t k) {
  auto length = [&](std::size_t i) {
    const std::size_t j = i + 1 < kVertebraCount ? i + 1 : i - 1;
    return (pose[i].body_center - pose[j].body_center).norm();
  };
  const std::size_t first = k < kFirstLumbarIndex ? 0 : kFirstLumbarIndex;
  const std::size_t last = k < kFirstLumbarIndex ? kFirstLumbarIndex : kVertebraCount;
  double total = 0;
  for (std::size_t i = first; i < last; ++i) total += length(i);
  return total > 0 ? length(k) / total : 0.0;
}

}  // namespace

SchultzResult schultz(const SchultzInputs& in) {
  SchultzResult r;
  // Eq. 22: l_E E = l_t W_t + l_h W_h + l_l W_l + l_r W_r.
  r.erector_n = (in.l_trunk * in.w_trunk + in.l_head * in.w_head + in.l_left_arm * in.w_left_arm +
                 in.l_right_arm * in.w_right_arm) /
                in.l_erector;
  // Eq. 21: C − E = W_t + W_h + W_l + W_r; together, Eq. 23.
  r.compression_n = r.erector_n + in.w_trunk + in.w_head + in.w_left_arm + in.w_right_arm;
  return r;
}

Result<LoadParams> parse_load_params(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  LoadParams p;
  auto body = detail::toml_table(*root, "body", source);
  if (!body) return body.error();
  if (auto s = detail::read_numbers(**body, source, "body",
                                    {{"mass_kg", &p.body_mass_kg, 20, 300},
                                     {"reference_height_mm", &p.reference_height_mm, 1000, 2300}});
      !s)
    return s.error();
  p.height_mm = p.reference_height_mm;
  auto fr = detail::toml_table(*root, "fractions", source);
  if (!fr) return fr.error();
  if (auto s = detail::read_numbers(**fr, source, "fractions",
                                    {{"head_neck", &p.head_neck, 0, 0.5}, {"thorax", &p.thorax, 0, 0.5},
                                     {"abdomen", &p.abdomen, 0, 0.5}, {"upper_arm", &p.upper_arm, 0, 0.2},
                                     {"forearm", &p.forearm, 0, 0.2}, {"hand", &p.hand, 0, 0.2}});
      !s)
    return s.error();
  auto geo = detail::toml_table(*root, "geometry", source);
  if (!geo) return geo.error();
  for (auto [key, out] : {std::pair{"head_com_mm", &p.head_com_mm}, std::pair{"shoulder_mm", &p.shoulder_mm}}) {
    auto v = vector3(**geo, key, source);
    if (!v) return v.error();
    *out = *v;
  }
  if (auto s = detail::read_numbers(**geo, source, "geometry",
                                    {{"arm_com_drop_mm", &p.arm_com_drop_mm, 0, 1000},
                                     {"trunk_com_anterior_mm", &p.trunk_com_anterior_mm, -200, 300},
                                     {"erector_lever_mm", &p.erector_lever_mm, 10, 300}});
      !s)
    return s.error();
  return p;
}

const LoadParams& default_load_params() {
  static const LoadParams params = [] {
    auto parsed = parse_load_params(segments_toml(), "config/segments.toml");
    // The embedded file is tested; failing here means the build embedded a broken file.
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return params;
}

SchultzInputs schultz_inputs(const SpinePose& pose, std::size_t level, const LoadParams& p) {
  const double weight = p.body_mass_kg * kGravity;
  const double s = p.height_mm / p.reference_height_mm;
  // Sagittal lever arms are horizontal distances along the pelvis's forward axis.
  Eigen::Vector3d forward = pose[kWaistIndex].q * Eigen::Vector3d::UnitX();
  forward.y() = 0;
  forward = forward.norm() > 1e-6 ? Eigen::Vector3d(forward.normalized()) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d& here = pose[level].body_center;
  auto lever = [&](const Eigen::Vector3d& com) { return (com - here).dot(forward); };

  SchultzInputs in;
  in.l_erector = p.erector_lever_mm * s;
  const VertebraPose& t1 = pose[kNeckIndex];
  in.w_head = p.head_neck * weight;
  in.l_head = lever(t1.body_center + t1.q * (p.head_com_mm * s));
  const double arm = (p.upper_arm + p.forearm + p.hand) * weight;
  for (double side : {1.0, -1.0}) {  // right (+Z), then left
    const Eigen::Vector3d shoulder =
        t1.body_center + t1.q * Eigen::Vector3d(p.shoulder_mm.x(), p.shoulder_mm.y(), side * p.shoulder_mm.z()) * s;
    const double l = lever(shoulder - Eigen::Vector3d(0, p.arm_com_drop_mm * s, 0));  // arms hang plumb
    (side > 0 ? in.w_right_arm : in.w_left_arm) = arm;
    (side > 0 ? in.l_right_arm : in.l_left_arm) = l;
  }
  double moment = 0;
  for (std::size_t k = 0; k <= level; ++k) {
    const double w = (k < kFirstLumbarIndex ? p.thorax : p.abdomen) * weight * slice_share(pose, k);
    in.w_trunk += w;
    moment += w * lever(pose[k].body_center + pose[k].q * Eigen::Vector3d(p.trunk_com_anterior_mm * s, 0, 0));
  }
  in.l_trunk = in.w_trunk > 0 ? moment / in.w_trunk : 0.0;
  return in;
}

std::vector<LevelLoad> compute_loads(const SpinePose& pose, const LoadParams& params) {
  std::vector<LevelLoad> loads;
  loads.reserve(kVertebraCount);
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const SchultzInputs in = schultz_inputs(pose, i, params);
    const SchultzResult r = schultz(in);
    // The erector can only pull: a net backward moment is left to the
    // abdominal wall and ligaments, which this model does not carry.
    const double weights = in.w_trunk + in.w_head + in.w_left_arm + in.w_right_arm;
    loads.push_back({std::string(kVertebraNames[i]), std::max(r.erector_n, 0.0) + weights});
  }
  return loads;
}

}  // namespace spinewatch

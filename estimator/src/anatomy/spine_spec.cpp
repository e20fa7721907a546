#include "spinewatch/estimator/anatomy/spine_spec.hpp"

#include <cmath>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/toml_fields.hpp"

namespace spinewatch {
Result<SpineSpec> parse_spine_spec(std::string_view text, std::string_view source) {
  auto parsed = detail::parse_toml(text, source);
  if (!parsed) return parsed.error();
  const toml::table& root = *parsed;
  SpineSpec spec;
  const toml::table* spine = root["spine"].as_table();
  if (!spine) return Error{fmt::format("{}: [spine]: missing", source)};
  struct Field { const char* key; double* out; double min, max; };
  for (const Field& f : {Field{"reference_height_mm", &spec.reference_height_mm, 1000, 2300},
                         Field{"l5_height_fraction", &spec.l5_height_fraction, 0.3, 0.8},
                         Field{"kyphosis_deg", &spec.kyphosis_deg, 0, 90},
                         Field{"lordosis_deg", &spec.lordosis_deg, 0, 90}}) {
    auto v = detail::toml_number(*spine, f.key, source, "spine", f.min, f.max);
    if (!v) return v.error();
    *f.out = *v;
  }

  const toml::array* vertebrae = root["vertebra"].as_array();
  if (!vertebrae || vertebrae->size() != kVertebraCount)
    return Error{fmt::format("{}: [[vertebra]]: expected {} entries T1…L5", source, kVertebraCount)};
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const toml::table* v = (*vertebrae)[i].as_table();
    const std::string ctx = fmt::format("vertebra[{}]", i);
    if (!v) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    auto name = (*v)["name"].value<std::string>();
    if (!name || *name != kVertebraNames[i])
      return Error{fmt::format("{}: {}.name: expected \"{}\"", detail::toml_where(source, *v), ctx, kVertebraNames[i])};
    VertebraSpec& out = spec.vertebrae[i];
    out.name = *name;
    for (auto [key, field, min] : {std::tuple{"height_mm", &out.height_mm, 1.0}, std::tuple{"width_mm", &out.width_mm, 1.0},
                                   std::tuple{"depth_mm", &out.depth_mm, 1.0}, std::tuple{"spacing_mm", &out.spacing_mm, 0.0}}) {
      auto value = detail::toml_number(*v, key, source, ctx, min, 200);
      if (!value) return value.error();
      *field = *value;
    }
    if (i + 1 < kVertebraCount && out.spacing_mm < 1.0)
      return Error{fmt::format("{}: {}.spacing_mm: must be positive above L5", detail::toml_where(source, *v), ctx)};
  }

  const toml::array* joints = root["joint"].as_array();
  if (!joints || joints->size() != kJointCount)
    return Error{fmt::format("{}: [[joint]]: expected {} entries T1-T2…L4-L5", source, kJointCount)};
  for (std::size_t i = 0; i < kJointCount; ++i) {
    const toml::table* j = (*joints)[i].as_table();
    const std::string ctx = fmt::format("joint[{}]", i);
    if (!j) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    const std::string expected = fmt::format("{}-{}", kVertebraNames[i], kVertebraNames[i + 1]);
    auto name = (*j)["name"].value<std::string>();
    if (!name || *name != expected)
      return Error{fmt::format("{}: {}.name: expected \"{}\"", detail::toml_where(source, *j), ctx, expected)};
    JointSpec& out = spec.joints[i];
    out.name = *name;
    for (auto [key, field, max] : {std::tuple{"flexion_deg", &out.flexion_deg, 60.0}, std::tuple{"lateral_deg", &out.lateral_deg, 45.0},
                                   std::tuple{"axial_deg", &out.axial_deg, 45.0}, std::tuple{"k_axial_n_per_mm", &out.k_axial_n_per_mm, 1e5}}) {
      auto value = detail::toml_number(*j, key, source, ctx, 0.01, max);
      if (!value) return value.error();
      *field = *value;
    }
  }
  return spec;
}

const SpineSpec& generic_spine_spec() {
  static const SpineSpec spec = [] {
    auto parsed = parse_spine_spec(generic_spine_toml(), "config/spine-generic.toml");
    // The embedded file is tested; failing here means the build embedded a broken file.
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return spec;
}

double size_scale(const SpineSpec& spec, double height_mm) { return height_mm / spec.reference_height_mm; }

SpinePose neutral_pose(const SpineSpec& spec, double height_mm, const Eigen::Vector3d& l5_center) {
  const double s = size_scale(spec, height_mm);
  SpinePose pose;
  pose[kWaistIndex].body_center = l5_center;
  // Walk up from L5. Each gap's direction follows the sagittal tangent,
  // which turns linearly from +lordosis/2 at L5 to −lordosis/2 at T12 and
  // from −kyphosis/2 at T12 to +kyphosis/2 at T1 (+ = rising anteriorly).
  constexpr std::size_t kT12 = 11;
  const double deg = M_PI / 180.0;
  for (std::size_t i = kWaistIndex; i-- > 0;) {
    const std::size_t gap = i;  // between vertebra i and i+1
    double theta;
    if (gap >= kT12) {
      const double u = (double(kWaistIndex - 1 - gap) + 0.5) / double(kWaistIndex - kT12);  // 0 at L5 → 1 at T12
      theta = spec.lordosis_deg * (0.5 - u);
    } else {
      const double u = (double(kT12 - 1 - gap) + 0.5) / double(kT12);  // 0 at T12 → 1 at T1
      theta = spec.kyphosis_deg * (u - 0.5);
    }
    const double d = spec.vertebrae[i].spacing_mm * s;
    pose[i].body_center = pose[i + 1].body_center + d * Eigen::Vector3d(std::sin(theta * deg), std::cos(theta * deg), 0);
  }
  return pose;
}

SpinePose neutral_pose(const SpineSpec& spec, double height_mm) {
  return neutral_pose(spec, height_mm, Eigen::Vector3d(0, spec.l5_height_fraction * height_mm, 0));
}

}  // namespace spinewatch

#include "spinewatch/estimator/spine/joint_stiffness.hpp"

#include <cmath>
#include <stdexcept>

#include "common/toml_fields.hpp"
#include "spinewatch/estimator/units.hpp"

namespace spinewatch {
namespace {

std::string at(std::string_view source, const toml::node& n) {
  return fmt::format("{}:{}", source, n.source().begin.line);
}

Status check_keys(const toml::table& t, std::string_view source, std::string_view ctx,
                  std::initializer_list<std::string_view> known) {
  for (auto&& [key, node] : t) {
    bool ok = false;
    for (std::string_view k : known) ok |= key.str() == k;
    if (!ok) return Error{fmt::format("{}: {}.{}: unknown key", at(source, node), ctx, key.str())};
  }
  return Ok{};
}

}  // namespace

Eigen::Vector3d JointStiffness::nm_per_rad() const {
  const Eigen::Vector3d range_rad(lateral_deg * kRadPerDeg, axial_deg * kRadPerDeg,
                                  0.5 * flexion_extension_deg * kRadPerDeg);
  return moment_nm * range_rad.cwiseInverse();
}

Result<JointStiffnessTable> parse_joint_stiffness(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  if (auto s = check_keys(*root, source, "file", {"joint"}); !s) return s.error();
  const toml::array* joints = (*root)["joint"].as_array();
  if (!joints || joints->size() != kJointCount)
    return Error{fmt::format("{}: [[joint]]: expected {} entries T1-T2…L4-L5", source, kJointCount)};
  JointStiffnessTable table;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    const toml::table* j = (*joints)[i].as_table();
    const std::string ctx = fmt::format("joint[{}]", i);
    if (!j) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    if (auto s = check_keys(*j, source, ctx,
                            {"name", "moment_nm", "flexion_extension_deg", "lateral_deg", "axial_deg", "source"});
        !s)
      return s.error();
    JointStiffness& out = table[i];
    out.name = fmt::format("{}-{}", kVertebraNames[i], kVertebraNames[i + 1]);
    auto name = (*j)["name"].value<std::string>();
    if (!name || *name != out.name)
      return Error{fmt::format("{}: {}.name: expected \"{}\"", at(source, *j), ctx, out.name)};
    auto src = (*j)["source"].value<std::string>();
    if (!src || src->empty())
      return Error{fmt::format("{}: {}.source: every figure names its source", at(source, *j), ctx)};
    out.source = *src;
    if (auto s = detail::read_numbers(*j, source, ctx,
                                      {{"moment_nm", &out.moment_nm, 0.5, 50},
                                       {"flexion_extension_deg", &out.flexion_extension_deg, 0.2, 60},
                                       {"lateral_deg", &out.lateral_deg, 0.1, 45},
                                       {"axial_deg", &out.axial_deg, 0.1, 45}});
        !s)
      return s.error();
  }
  return table;
}

const JointStiffnessTable& generic_joint_stiffness() {
  static const JointStiffnessTable table = [] {
    auto parsed = parse_joint_stiffness(joint_stiffness_toml(), "config/spine-stiffness.toml");
    // The embedded file is tested; failing here means the build embedded a broken file.
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return table;
}

}  // namespace spinewatch

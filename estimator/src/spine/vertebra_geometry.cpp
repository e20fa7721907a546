#include "spinewatch/estimator/spine/vertebra_geometry.hpp"

#include <cmath>
#include <stdexcept>

#include "common/toml_fields.hpp"

namespace spinewatch {
namespace {

Status read_posterior(const toml::table& root, std::string_view path, std::string_view source,
                      PosteriorElements& p) {
  auto t = detail::toml_table(root, path, source);
  if (!t) return t.error();
  return detail::read_numbers(**t, source, path,
                              {{"pedicle_width", &p.pedicle_width, 0.01, 1},
                               {"pedicle_height", &p.pedicle_height, 0.01, 1.5},
                               {"pedicle_length", &p.pedicle_length, 0.01, 2},
                               {"pedicle_spacing", &p.pedicle_spacing, 0.0, 1.5},
                               {"lamina_thickness", &p.lamina_thickness, 0.01, 2},
                               {"lamina_height", &p.lamina_height, 0.01, 2},
                               {"spinous_length", &p.spinous_length, 0.01, 3},
                               {"spinous_height", &p.spinous_height, 0.01, 2},
                               {"spinous_width", &p.spinous_width, 0.01, 1},
                               {"spinous_droop_deg", &p.spinous_droop_deg, 0, 80},
                               {"transverse_reach", &p.transverse_reach, 0.1, 2},
                               {"transverse_thickness", &p.transverse_thickness, 0.01, 1}});
}

OrientedBox box(const Eigen::Vector3d& centre, const Eigen::Vector3d& half,
                const Eigen::Matrix3d& axes = Eigen::Matrix3d::Identity()) {
  return OrientedBox{centre, axes, half};
}

}  // namespace

Result<VertebraGeometry> parse_vertebra_geometry(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  VertebraGeometry g;
  auto bone = detail::toml_table(*root, "bone", source);
  if (!bone) return bone.error();
  if (auto s = detail::read_numbers(**bone, source, "bone", {{"density_kg_per_m3", &g.bone_density_kg_per_m3, 100, 3000}}); !s)
    return s.error();
  if (auto s = read_posterior(*root, "posterior.thoracic", source, g.thoracic); !s) return s.error();
  if (auto s = read_posterior(*root, "posterior.lumbar", source, g.lumbar); !s) return s.error();
  auto disc = detail::toml_table(*root, "disc", source);
  if (!disc) return disc.error();
  DiscFigures& d = g.disc;
  if (auto s = detail::read_numbers(**disc, source, "disc",
                                    {{"attach_fraction", &d.attach_fraction, 0.05, 1},
                                     {"max_spring_bending_share", &d.max_spring_bending_share, 0.0, 0.95},
                                     {"damping_n_s_per_m", &d.damping_n_s_per_m, 0, 1e5},
                                     {"tension_ratio", &d.tension_ratio, 0.0, 1},
                                     {"shear_fraction", &d.shear_fraction, 0.0, 1}});
      !s)
    return s.error();
  return g;
}

const VertebraGeometry& generic_vertebra_geometry() {
  static const VertebraGeometry geometry = [] {
    auto parsed = parse_vertebra_geometry(vertebra_geometry_toml(), "config/vertebra-geometry.toml");
    // The embedded file is tested; failing here means the build embedded a broken file.
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return geometry;
}

Solid vertebral_body_solid(const BodyDims& d) {
  Solid s;
  s.cylinders.push_back({Eigen::Vector3d::Zero(), d.depth_mm / 2, d.width_mm / 2, d.height_mm / 2});
  return s;
}

Solid vertebra_solid(const BodyDims& d, const PosteriorElements& p) {
  Solid s = vertebral_body_solid(d);
  const double w = d.width_mm, h = d.height_mm, dep = d.depth_mm;
  const double back = -dep / 2;  // posterior wall of the body
  // Pedicles overlap the body by a millimetre so the union is one piece.
  const double pl = p.pedicle_length * dep;
  const double pz = p.pedicle_spacing * w / 2;
  for (double side : {-1.0, 1.0})
    s.boxes.push_back(box({back - pl / 2 + 0.5, 0, side * pz},
                          {pl / 2 + 0.5, p.pedicle_height * h / 2, p.pedicle_width * w / 2}));
  // Laminae: one plate closing the arch behind the pedicles.
  const double lt = p.lamina_thickness * dep;
  const double arch_back = back - pl - lt;
  s.boxes.push_back(box({back - pl - lt / 2, 0, 0}, {lt / 2, p.lamina_height * h / 2, pz + p.pedicle_width * w / 2}));
  // Spinous process: from the back of the arch, pointing posteriorly and down.
  const double droop = p.spinous_droop_deg * M_PI / 180.0;
  const Eigen::Vector3d along(-std::cos(droop), -std::sin(droop), 0);
  const Eigen::Vector3d across(std::sin(droop), -std::cos(droop), 0);
  Eigen::Matrix3d axes;
  axes << along, across, Eigen::Vector3d::UnitZ();
  const double sl = p.spinous_length * dep;
  s.boxes.push_back(box(Eigen::Vector3d(arch_back + lt / 2, 0, 0) + along * (sl / 2),
                        {sl / 2 + lt / 4, p.spinous_height * h / 2, p.spinous_width * w / 2}, axes));
  // Transverse processes: from the pedicle-lamina junction out to each side.
  const double reach = p.transverse_reach * w;
  const double half_len = (reach - pz) / 2;
  for (double side : {-1.0, 1.0})
    s.boxes.push_back(box({back - pl - lt / 2, 0, side * (pz + half_len)},
                          {p.transverse_thickness * dep / 2, p.transverse_thickness * h / 2, half_len}));
  return s;
}

}  // namespace spinewatch

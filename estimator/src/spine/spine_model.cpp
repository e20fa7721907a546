#include "spinewatch/estimator/spine/spine_model.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch {
namespace {

VertebraBody build_body(std::size_t i, const BodyDims& dims, const SpineModelOptions& o) {
  VertebraBody b;
  b.name = std::string(kVertebraNames[i]);
  b.dims = dims;
  const PosteriorElements& posterior = i >= kFirstLumbarIndex ? o.geometry.lumbar : o.geometry.thoracic;
  const std::vector<Eigen::Vector3d> particles = voxelise(vertebra_solid(dims, posterior), o.voxel_mm);
  const double v = o.voxel_mm * 1e-3;
  const double particle_kg = o.geometry.bone_density_kg_per_m3 * v * v * v;
  b.particles = particles.size();
  b.mass = mass_properties(particles, particle_kg, o.voxel_mm);
  const std::vector<Eigen::Vector3d> body = voxelise(vertebral_body_solid(dims), o.voxel_mm);
  b.body_centroid_mm = mass_properties(body, particle_kg).com_mm;
  return b;
}

// Bending stiffness the springs give about the disc centre, N·m/rad, in world axes.
Eigen::Matrix3d spring_bending(const std::vector<Eigen::Vector3d>& upper, const std::vector<Eigen::Vector3d>& lower,
                               const std::vector<double>& k_n_per_mm, const Eigen::Vector3d& centre) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  for (std::size_t s = 0; s < upper.size(); ++s) {
    const Eigen::Vector3d u = (upper[s] - lower[s]).normalized();
    const Eigen::Vector3d arm = ((upper[s] - centre) * 1e-3).cross(u);  // m
    K += k_n_per_mm[s] * 1e3 * arm * arm.transpose();
  }
  return K;
}

Disc build_disc(std::size_t j, const VertebraPose& up, const VertebraPose& low, const BodyDims& du,
                const BodyDims& dl, const SpineModelOptions& o) {
  const DiscFigures& f = o.geometry.disc;
  const JointSpec& js = o.spec.joints[j];
  Disc disc;
  disc.rest_relative = (low.q.conjugate() * up.q).normalized();

  const Eigen::Vector3d centre = 0.5 * (up.body_center + low.body_center);
  const Eigen::Vector3d axis = (up.body_center - low.body_center).normalized();
  const double gap = std::max(2.0, (up.body_center - low.body_center).norm() - 0.5 * (du.height_mm + dl.height_mm));
  Eigen::Vector3d anterior = low.q * Eigen::Vector3d::UnitX();
  anterior = (anterior - anterior.dot(axis) * axis).normalized();
  const Eigen::Vector3d lateral = anterior.cross(axis);

  // Joint stiffness from published in-vitro moment–rotation figures
  // (config/spine-stiffness.toml), not from the ranges the phantom moves by.
  disc.range_stiffness_nm_per_rad = o.stiffness[j].nm_per_rad();

  double a = f.attach_fraction * 0.5 * std::min(du.depth_mm, dl.depth_mm);  // along `anterior`
  double b = f.attach_fraction * 0.5 * std::min(du.width_mm, dl.width_mm);  // along `lateral`
  std::vector<Eigen::Vector3d> upper, lower;
  std::vector<double> k;
  const double k_axial = js.k_axial_n_per_mm;
  auto layout = [&] {
    upper.clear();
    lower.clear();
    k.clear();
    const std::array<Eigen::Vector3d, 4> offsets = {a * anterior, -a * anterior, b * lateral, -b * lateral};
    // Crossed springs (through the centre) give the shear stiffness; their
    // axial share is taken off the straight ones so the axial total is k_axial.
    double crossed_axial = 0;
    std::array<double, 4> k_crossed{};
    for (std::size_t s = 0; s < 4; ++s) {
      const double len = std::hypot(gap, 2 * offsets[s].norm());
      const double sin2 = std::pow(2 * offsets[s].norm() / len, 2);
      k_crossed[s] = f.shear_fraction * k_axial / (2 * sin2);
      crossed_axial += k_crossed[s] * (1 - sin2);
    }
    const double k_straight = std::max(0.25 * (k_axial - crossed_axial), 0.05 * k_axial);
    for (std::size_t s = 0; s < 4; ++s) {  // symmetric about the disc centre
      upper.push_back(centre + offsets[s] + 0.5 * gap * axis);
      lower.push_back(centre + offsets[s] - 0.5 * gap * axis);
      k.push_back(k_straight);
    }
    for (std::size_t s = 0; s < 4; ++s) {
      upper.push_back(centre + offsets[s] + 0.5 * gap * axis);
      lower.push_back(centre - offsets[s] - 0.5 * gap * axis);
      k.push_back(k_crossed[s]);
    }
  };
  // Shrink the attachment ellipse until the springs carry at most their
  // share of the joint's bending stiffness (lateral bend ∝ b², flexion ∝ a²).
  const Eigen::Matrix3d Rl = low.q.toRotationMatrix();
  Eigen::Vector3d spring_k = Eigen::Vector3d::Zero();
  for (int pass = 0; pass < 3; ++pass) {
    layout();
    spring_k = (Rl.transpose() * spring_bending(upper, lower, k, centre) * Rl).diagonal();
    const Eigen::Vector3d allowed = f.max_spring_bending_share * disc.range_stiffness_nm_per_rad;
    if (spring_k.x() > allowed.x()) b *= std::sqrt(allowed.x() / spring_k.x());
    if (spring_k.z() > allowed.z()) a *= std::sqrt(allowed.z() / spring_k.z());
  }
  layout();
  spring_k = (Rl.transpose() * spring_bending(upper, lower, k, centre) * Rl).diagonal();
  disc.rotational_spring_nm_per_rad =
      (disc.range_stiffness_nm_per_rad - spring_k).cwiseMax((1 - f.max_spring_bending_share) *
                                                           disc.range_stiffness_nm_per_rad);

  for (std::size_t s = 0; s < upper.size(); ++s) {
    DiscSpring spring;
    spring.upper_local_mm = up.q.conjugate() * (upper[s] - up.body_center);
    spring.lower_local_mm = low.q.conjugate() * (lower[s] - low.body_center);
    spring.rest_length_mm = (upper[s] - lower[s]).norm();  // rest lengths from the initial posture (Eq. 10, l⁰)
    spring.k_compression_n_per_mm = k[s];
    spring.k_tension_n_per_mm = f.tension_ratio * k[s];
    spring.damping_n_s_per_m = s < 4 ? 0.25 * f.damping_n_s_per_m : 0.0;
    disc.springs.push_back(spring);
  }
  return disc;
}

}  // namespace

SpineModel SpineModel::from_subject(const SubjectSpine& subject, const SpineModelOptions& options) {
  SpineModel m;
  m.spec_ = options.spec;
  m.voxel_mm_ = options.voxel_mm;
  m.neutral_ = neutral_of(subject);
  for (std::size_t i = 0; i < kVertebraCount; ++i) m.bodies_[i] = build_body(i, subject[i].dims, options);
  for (std::size_t j = 0; j < kJointCount; ++j)
    m.discs_[j] = build_disc(j, subject[j].pose, subject[j + 1].pose, subject[j].dims, subject[j + 1].dims, options);
  return m;
}

SpineModel SpineModel::generic(double height_mm, const SpineModelOptions& options) {
  return from_subject(generic_subject(height_mm), options);
}

Result<SpineModel> SpineModel::from_subject_file(const std::filesystem::path& path, const SpineModelOptions& options) {
  auto subject = load_subject_file(path);
  if (!subject) return subject.error();
  return from_subject(*subject, options);
}

}  // namespace spinewatch

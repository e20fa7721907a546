#pragma once
// The accurate spine model (paper §2.2): 17 vertebrae as particle bodies,
// joined by discs of Eq. 10 springs plus a rotational spring per joint, all
// at rest in the subject's neutral posture.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/spine/joint_stiffness.hpp"
#include "spinewatch/estimator/spine/mass_properties.hpp"
#include "spinewatch/estimator/spine/subject.hpp"
#include "spinewatch/estimator/spine/vertebra_geometry.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct SpineModelOptions {
  double voxel_mm = 1.0;
  VertebraGeometry geometry = generic_vertebra_geometry();
  SpineSpec spec = generic_spine_spec();  // ranges of motion (the anatomical limits) and disc axial stiffness
  JointStiffnessTable stiffness = generic_joint_stiffness();  // bending and torsion, published in vitro
};

struct VertebraBody {
  std::string name;
  BodyDims dims;
  std::size_t particles = 0;
  // Local frame, origin at the body centre. `mass.com_mm` is the centre of
  // mass of the whole vertebra (posterior elements included);
  // `body_centroid_mm` that of the vertebral body's particles alone (≈ 0).
  MassProperties mass;
  Eigen::Vector3d body_centroid_mm = Eigen::Vector3d::Zero();
};

// One Eq. 10 spring between the upper vertebra's inferior endplate and the
// lower one's superior endplate.
struct DiscSpring {
  Eigen::Vector3d upper_local_mm, lower_local_mm;  // attachment, each in its body's frame
  double rest_length_mm = 0;
  double k_compression_n_per_mm = 0, k_tension_n_per_mm = 0;
  double damping_n_s_per_m = 0;
};

struct Disc {  // joint i joins vertebra i (upper) and i + 1 (lower)
  std::vector<DiscSpring> springs;
  // Total bending stiffness of the joint (SpineModelOptions::stiffness), about
  // the lower vertebra's X (lateral bend), Y (twist), Z (flexion) axes, N·m/rad;
  // and the share the rotational spring adds to the springs' own.
  Eigen::Vector3d range_stiffness_nm_per_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotational_spring_nm_per_rad = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rest_relative = Eigen::Quaterniond::Identity();  // lower⁻¹ · upper at rest
};

class SpineModel {
 public:
  static SpineModel generic(double height_mm, const SpineModelOptions& options = {});
  static SpineModel from_subject(const SubjectSpine& subject, const SpineModelOptions& options = {});
  static Result<SpineModel> from_subject_file(const std::filesystem::path& path,
                                              const SpineModelOptions& options = {});

  const SpinePose& neutral() const { return neutral_; }
  const VertebraBody& vertebra(std::size_t i) const { return bodies_[i]; }
  const Disc& disc(std::size_t joint) const { return discs_[joint]; }
  const SpineSpec& spec() const { return spec_; }
  double voxel_mm() const { return voxel_mm_; }

 private:
  SpineModel() = default;
  SpinePose neutral_;
  std::array<VertebraBody, kVertebraCount> bodies_;
  std::array<Disc, kJointCount> discs_;
  SpineSpec spec_;
  double voxel_mm_ = 1.0;
};

}  // namespace spinewatch

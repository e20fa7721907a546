#pragma once
// The Connected Vertebra Spheres Model (paper §2.1): spheres T1…L5 on the
// spine, each holding a control plane of body-outline control points, plus
// the control planes of what the silhouettes also show (pelvis, neck and
// head, arms, legs). The outer shape is the solid between adjacent control
// planes of a chain.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

inline constexpr int kControlPoints = 12;  // every 30°

// config/cvsm-generic.toml: every length a fraction of standing height.
struct CvsmSpec {
  struct Trunk {
    double half_width = 0, depth = 0, spine_fraction = 0.3;
  };
  struct Part {
    std::string chain;   // pelvis | head | arm | leg
    std::string attach;  // vertebra name or "hip"
    double y = 0, x = 0, z = 0;
    double half_width = 0, front = 0, back = 0;
  };
  std::array<Trunk, kVertebraCount> trunk{};
  std::vector<Part> parts;
  double hip_y = 0.53, hip_x = 0, hip_z = 0.05, thigh = 0.245;
};
Result<CvsmSpec> parse_cvsm_spec(std::string_view toml_text, std::string_view source);
const CvsmSpec& generic_cvsm_spec();
std::string_view generic_cvsm_toml();

enum class SubjectPosture : std::uint8_t { Standing, Seated };

// What makes a subject's model differ from the generic one.
struct BodyShape {
  double height_mm = 1750;
  double width_scale = 1.0;     // trunk, pelvis and head half-widths
  double depth_scale = 1.0;     // trunk, pelvis and head depths
  double shoulder_scale = 1.0;  // lateral offset of the arms
  double limb_scale = 1.0;      // arm and leg girth
  // Neck length and head height relative to the generic proportions (the
  // head's planes sit this much farther above T1): people differ far more
  // in where their head ends than the height fractions of the trunk say,
  // and the measured crown must not drag the spine up or down.
  double head_scale = 1.0;
  // Measured per-level trunk depths (mm), overriding depth × depth_scale
  // where > 0; the spine keeps its generic fraction of the depth.
  std::array<double, kVertebraCount> measured_depth_mm{};
  // Per level, the body centre's depth in front of the back skin (mm) by
  // the published rule (anatomy/spine_depth.hpp) where > 0; else the
  // template's spine fraction of the trunk depth (the generic placement).
  std::array<double, kVertebraCount> spine_depth_mm{};
  SubjectPosture posture = SubjectPosture::Standing;
  // The stature the spine was placed for (measured placement: the crown
  // standing, the searched height seated or with the crown in neither
  // view); 0 with the generic placement.
  double stature_mm = 0;
  // stature_mm is the crown the views measured standing, not a height the
  // fit chose (nor a given stature).
  bool stature_measured = false;
};

// One control plane: a 12-point ellipse-like ring in its frame's XZ plane
// (or YZ plane when axis_x, for horizontal limbs).
struct ControlPlane {
  int frame = 0;              // 0…16 vertebra, kLegLeftFrame, kLegRightFrame
  Eigen::Vector3d offset{0, 0, 0};  // ring centre in the frame, mm
  bool axis_x = false;
  double half_width = 0, front = 0, back = 0;  // mm
  bool vertebra = false;      // the ring of one of the spheres T1…L5
  int joint = -1;             // the limb joint that turns it (JointId), -1: none
};
inline constexpr int kLegLeftFrame = 17, kLegRightFrame = 18, kFrameCount = 19;

// The articulated limbs' joints (docs/cvsm.md, "Articulated limbs"). A
// plane turned by a joint turns with its parent too (the forearm with the
// upper arm, the shin with the thigh).
enum class JointId : std::uint8_t {
  ShoulderLeft, ElbowLeft, ShoulderRight, ElbowRight, HipLeft, KneeLeft, HipRight, KneeRight, Neck
};
inline constexpr std::size_t kLimbJointCount = 9;
struct Joint {
  int frame = 0;                   // the frame its pivot is given in (the plane's)
  Eigen::Vector3d pivot{0, 0, 0};  // in that frame, mm
  int parent = -1;                 // the joint whose turn carries this one, -1: none
};

// The subject-specific model: control planes and chains (indices into
// planes, adjacent entries bound one solid segment).
struct BodyModel {
  BodyShape shape;
  SpinePose neutral;                       // spine neutral pose, L5 at base_l5
  std::vector<ControlPlane> planes;
  std::vector<std::vector<int>> chains;
  Eigen::Vector3d hip_left{0, 0, 0}, hip_right{0, 0, 0};  // hip joints in L5's frame
  // Local control-point offsets, planes.size() × kControlPoints, in each frame.
  std::vector<Eigen::Vector3d> local_points;
  // Per plane, whether a chain uses it: all of them in a built model, not
  // the skipped vertebra rings in a thinned one. Set with the chains.
  std::vector<std::uint8_t> in_chain;
  std::array<Joint, kLimbJointCount> joints{};  // pivots at the neutral limbs
};

// neutral L5 body centre: (x, l5_height_fraction·H or seat, z).
BodyModel build_body_model(const CvsmSpec& spec, const SpineSpec& spine, const BodyShape& shape,
                           const Eigen::Vector3d& l5_center);

// The limbs and the head, turned from where the model holds them
// (arms hanging slightly abducted with the elbows a little flexed; legs
// hanging, or the seated thigh forward and shin down), degrees. Frames:
// X anterior, Y up, Z right. All zero: the model as built, every point
// computed as without articulation.
struct LimbPose {
  struct Side {
    double shoulder_flexion = 0;    // the arm raised forward (about Z)
    double shoulder_abduction = 0;  // the arm raised to the side (about the body's X, outward positive)
    double elbow = 0;               // the forearm turned forward about the elbow
    double hip_flexion = 0;         // the thigh forward
    double hip_abduction = 0;       // the leg out to the side
    double knee = 0;                // the shin back about the knee
  };
  std::array<Side, 2> side{};  // [0] left, [1] right
  double head_flexion = 0;     // nod forward, about the neck's base
  double head_lateral = 0;     // tilt to the right
  double head_turn = 0;        // turn about the neck (to the subject's left positive: about +Y)
  bool neutral() const;
};

// The primitive deformations: whole-spine flexion/extension, lateral
// bending and axial twist spread over the levels by range of motion
// (distribute()), pelvis tilt and translation; and the limbs.
struct CvsmPose {
  double flexion = 0, lateral = 0, twist = 0;      // degrees, whole spine
  double pelvis_flexion = 0, pelvis_lateral = 0;   // degrees, about the hip joints
  Eigen::Vector3d translation{0, 0, 0};            // mm, of the hip joints (and L5) from neutral
  LimbPose limbs;                                   // articulated limbs ([cvsm] limbs = "articulated")
  // Which way the whole body faces: a turn about the world's vertical
  // through the hip joints, degrees, counter-clockwise seen from above
  // (0: facing the frontal camera, +X; 90: facing −Z; 180: the back to the
  // frontal camera). Applied last, so every other parameter is the body's
  // own (docs/cvsm.md, "Heading").
  double heading = 0;
};

// The same model with only every `keep`-th vertebra ring in the trunk
// chain (T1 and L5 always kept): the search's coarse outline. Planes and
// control points are unchanged, so the same points serve both.
BodyModel thin_trunk(const BodyModel& model, int keep);

SpinePose pose_vertebrae(const BodyModel& model, const SpineSpec& spine, const CvsmPose& pose);
// World control points (planes.size() × kControlPoints) of the planes the
// model's chains use (in a thinned model the skipped rings are left as
// they were), the limbs turned by `limbs`; `heading_deg` is the pose's
// heading (the vertebrae are already turned by it; the legs hang in its
// frame).
void control_points(const BodyModel& model, const SpinePose& vertebrae, std::vector<Eigen::Vector3d>& out,
                    const LimbPose& limbs = {}, double heading_deg = 0);
// The heading's turn about the world's vertical (CvsmPose::heading).
Eigen::Matrix3d heading_rotation(double heading_deg);
// Each joint's turn alone, in its frame (tests: the reference chain).
Eigen::Matrix3d limb_joint_rotation(JointId joint, const LimbPose& limbs);

}  // namespace spinewatch

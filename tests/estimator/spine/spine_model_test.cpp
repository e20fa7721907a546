// Particle bodies (Eqs. 1–9), vertebra solids, SUBJECT.json and the model's
// discs.
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <fmt/format.h>

#include "spine_truth.hpp"
#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/spine_model.hpp"
#include "spinewatch/estimator/spine/stiffness_fit.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(MassProperties, VoxelisedBoxMatchesAnalyticValues) {
  Solid box;
  // Off-centre and rotated 30° about Y so every tensor element is exercised.
  const Eigen::Matrix3d axes = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // Faces off the voxel grid: a face on it would add a whole layer of cells.
  box.boxes.push_back({Eigen::Vector3d(3.25, -2.25, 5.25), axes, Eigen::Vector3d(10, 5, 15)});
  const double voxel = 0.5, rho = 1000.0;  // kg/m³
  const auto particles = voxelise(box, voxel);
  const double pm = rho * std::pow(voxel * 1e-3, 3);
  const MassProperties mp = mass_properties(particles, pm, voxel);

  const double volume_m3 = 20e-3 * 10e-3 * 30e-3;
  EXPECT_NEAR(mp.mass_kg, rho * volume_m3, 0.02 * rho * volume_m3);
  EXPECT_LT((mp.com_mm - Eigen::Vector3d(3.25, -2.25, 5.25)).norm(), 0.3);
  // Analytic tensor in the box frame, rotated into the world: I = R diag Rᵀ.
  const double m = mp.mass_kg, a = 20, b = 10, c = 30;
  const Eigen::Vector3d principal(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12);
  const Eigen::Matrix3d expected = axes * principal.asDiagonal() * axes.transpose();
  EXPECT_LT((mp.inertia_kg_mm2 - expected).norm() / expected.norm(), 0.03);
  EXPECT_GT(std::abs(mp.inertia_kg_mm2(0, 2)), 0.1 * expected.norm());  // a product of inertia is present
}

TEST(MassProperties, AxisAlignedBoxIsExactWithVoxelSelfInertia) {
  Solid box;
  box.boxes.push_back({Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), Eigen::Vector3d(10, 5, 15)});
  const auto particles = voxelise(box, 1.0);
  ASSERT_EQ(particles.size(), std::size_t(21 * 11 * 31));  // cells centred on whole millimetres, faces included
  // Treat each particle as a 1 mm cube of 1 g: the solid is then a 21×11×31 mm box.
  const MassProperties mp = mass_properties(particles, 1e-3, 1.0);
  const double m = mp.mass_kg;
  EXPECT_NEAR(mp.inertia_kg_mm2(0, 0), m * (11.0 * 11 + 31.0 * 31) / 12, 1e-9 * m * 1000);
  EXPECT_NEAR(mp.inertia_kg_mm2(1, 1), m * (21.0 * 21 + 31.0 * 31) / 12, 1e-9 * m * 1000);
  EXPECT_NEAR(mp.inertia_kg_mm2(2, 2), m * (21.0 * 21 + 11.0 * 11) / 12, 1e-9 * m * 1000);
  EXPECT_NEAR(mp.inertia_kg_mm2(0, 1), 0.0, 1e-9);
}

TEST(MassProperties, VoxelisedEllipticCylinderMatchesAnalyticValues) {
  Solid cyl;
  cyl.cylinders.push_back({Eigen::Vector3d(0, 4, 0), 17.5, 23.0, 14.0});  // an L3 body: depth 35, width 46, height 28
  const double voxel = 0.5;
  const auto particles = voxelise(cyl, voxel);
  const MassProperties mp = mass_properties(particles, 1e-6, voxel);
  const double a = 17.5, b = 23.0, h = 28.0;
  const double volume_mm3 = M_PI * a * b * h;
  EXPECT_NEAR(double(particles.size()) * std::pow(voxel, 3), volume_mm3, 0.02 * volume_mm3);
  const double m = mp.mass_kg;
  EXPECT_LT((mp.com_mm - Eigen::Vector3d(0, 4, 0)).norm(), 0.05);
  EXPECT_NEAR(mp.inertia_kg_mm2(1, 1), m * (a * a + b * b) / 4, 0.02 * m * (a * a + b * b) / 4);
  EXPECT_NEAR(mp.inertia_kg_mm2(0, 0), m * (b * b / 4 + h * h / 12), 0.02 * m * (b * b / 4 + h * h / 12));
  EXPECT_NEAR(mp.inertia_kg_mm2(2, 2), m * (a * a / 4 + h * h / 12), 0.02 * m * (a * a / 4 + h * h / 12));
}

// voxelise() tests each primitive on its own bounds only; it must give
// exactly the reference's points (every voxel against every primitive),
// in the same order, so the masses and inertias do not move by a bit:
// every vertebra solid at three sizes, and random unions of
// turned boxes and cylinders whose faces fall on and off the grid.
TEST(MassProperties, VoxeliseGivesTheReferencesPointsInItsOrder) {
  const VertebraGeometry& g = generic_vertebra_geometry();
  for (const BodyDims dims : {BodyDims{18, 30, 20}, BodyDims{24, 40, 28}, BodyDims{28, 50, 35}})
    for (const PosteriorElements* posterior : {&g.thoracic, &g.lumbar})
      for (const Solid& solid : {vertebra_solid(dims, *posterior), vertebral_body_solid(dims)})
        for (double voxel : {1.0, 1.3}) {  // the model's, and one whose grid falls elsewhere
          const auto fast = voxelise(solid, voxel), reference = voxelise_reference(solid, voxel);
          ASSERT_FALSE(reference.empty());
          ASSERT_EQ(fast, reference) << dims.height_mm << " mm body, voxel " << voxel;
        }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Solid solid;
    const int parts = 1 + trial % 4;
    for (int p = 0; p < parts; ++p) {
      // Every fourth centre and size on whole millimetres: faces on the grid.
      auto value = [&](double scale) { return trial % 4 == 0 ? std::round(scale * u(rng)) : scale * u(rng); };
      const Eigen::Vector3d centre(value(20), value(20), value(20));
      if ((trial + p) % 2) {
        solid.cylinders.push_back({centre, 2 + std::abs(value(8)), 2 + std::abs(value(8)), 1 + std::abs(value(8))});
      } else {
        const Eigen::Matrix3d axes =
            Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
        solid.boxes.push_back({centre, trial % 8 == 0 ? Eigen::Matrix3d::Identity() : axes,
                               Eigen::Vector3d(1 + std::abs(value(9)), 1 + std::abs(value(9)), 1 + std::abs(value(9)))});
      }
    }
    const double voxel = trial % 3 == 0 ? 1.0 : 0.5 + std::abs(u(rng));
    ASSERT_EQ(voxelise(solid, voxel), voxelise_reference(solid, voxel)) << "trial " << trial;
  }
  EXPECT_TRUE(voxelise(Solid{}, 1.0).empty());
}

TEST(VertebraGeometry, EmbeddedFileParsesAndBadValuesAreNamed) {
  const VertebraGeometry& g = generic_vertebra_geometry();
  EXPECT_GT(g.bone_density_kg_per_m3, 1000);
  EXPECT_NEAR(g.disc.tension_ratio, 0.1, 1e-12);
  std::string text(vertebra_geometry_toml());
  const auto pos = text.find("density_kg_per_m3 = 1250.0");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 26, "density_kg_per_m3 = -5.0");
  auto bad = parse_vertebra_geometry(text, "geo.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("geo.toml:"), std::string::npos) << bad.error().message;
  EXPECT_NE(bad.error().message.find("bone.density_kg_per_m3"), std::string::npos) << bad.error().message;
}

// Built once: voxelising 17 vertebrae at 1 mm is the slow part under ASan.
const SpineModel& generic_model() {
  static const SpineModel model = SpineModel::generic(1750);
  return model;
}

TEST(SpineModel, VertebraeArePosteriorHeavyParticleBodies) {
  const SpineModel& model = generic_model();
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const VertebraBody& b = model.vertebra(i);
    EXPECT_GT(b.mass.mass_kg, 0.004) << b.name;
    EXPECT_LT(b.mass.mass_kg, 0.12) << b.name;
    // The body centroid (what body_center reports) sits at the local origin;
    // the whole vertebra's centre of mass lies behind it (posterior elements).
    EXPECT_LT(b.body_centroid_mm.norm(), 0.6) << b.name;
    EXPECT_LT(b.mass.com_mm.x(), -3.0) << b.name;
    EXPECT_NEAR(b.mass.com_mm.z(), 0.0, 0.5) << b.name;  // left-right symmetric
    // Principal moments are positive and satisfy the triangle inequality.
    const Eigen::Vector3d I = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(b.mass.inertia_kg_mm2).eigenvalues();
    EXPECT_GT(I.minCoeff(), 0) << b.name;
    EXPECT_LE(I[2], I[0] + I[1] + 1e-9) << b.name;
  }
  EXPECT_GT(model.vertebra(kWaistIndex).mass.mass_kg, 2 * model.vertebra(kNeckIndex).mass.mass_kg);
}

TEST(SpineModel, DiscSpringsAreSymmetricAboutTheDiscCentre) {
  const SpineModel& model = generic_model();
  const SpinePose& n = model.neutral();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const Disc& d = model.disc(j);
    const Eigen::Vector3d centre = 0.5 * (n[j].body_center + n[j + 1].body_center);
    Eigen::Vector3d sum_upper = Eigen::Vector3d::Zero(), sum_lower = Eigen::Vector3d::Zero();
    for (const DiscSpring& s : d.springs) {
      sum_upper += n[j].body_center + n[j].q * s.upper_local_mm - centre;
      sum_lower += n[j + 1].body_center + n[j + 1].q * s.lower_local_mm - centre;
      EXPECT_NEAR(s.k_tension_n_per_mm, 0.1 * s.k_compression_n_per_mm, 1e-9);
    }
    // Attachments balance about the centre: the upper set's mean is as far
    // above it as the lower set's is below.
    EXPECT_LT((sum_upper + sum_lower).norm(), 1e-9) << j;
    // The joint's stiffness is the published test moment over the range it
    // produced (config/spine-stiffness.toml), about each axis.
    const JointStiffness& js = generic_joint_stiffness()[j];
    EXPECT_NEAR(d.range_stiffness_nm_per_rad.x() * js.lateral_deg * M_PI / 180, js.moment_nm, 1e-9);
    EXPECT_NEAR(d.range_stiffness_nm_per_rad.y() * js.axial_deg * M_PI / 180, js.moment_nm, 1e-9);
    EXPECT_NEAR(d.range_stiffness_nm_per_rad.z() * 0.5 * js.flexion_extension_deg * M_PI / 180, js.moment_nm, 1e-9);
    EXPECT_GT(d.rotational_spring_nm_per_rad.minCoeff(), 0);
  }
}

TEST(Subject, RoundTripsAndBuildsTheSameNeutral) {
  const auto truth = test::make_subject(1900, 0.7);
  test::TempDir dir;
  test::write_file(dir / "subject.json", subject_to_json(truth.spine));
  SpineModelOptions coarse;
  coarse.voxel_mm = 2.0;
  auto model = SpineModel::from_subject_file(dir / "subject.json", coarse);
  ASSERT_TRUE(model) << model.error().message;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    EXPECT_LT((model->neutral()[i].body_center - truth.spine[i].pose.body_center).norm(), 1e-9);
    EXPECT_NEAR(model->vertebra(i).dims.width_mm, truth.spine[i].dims.width_mm, 1e-9);
  }
}

TEST(Subject, ErrorsNameTheFileAndTheField) {
  const std::string good = subject_to_json(generic_subject(1750));
  struct Case {
    std::string from, to, field;
  };
  for (const Case& c : {Case{"\"T3\"", "\"T9\"", "vertebrae[2].name"},
                        Case{"\"height_mm\": 15.5", "\"height_mm\": -1", "vertebrae[2].height_mm"},
                        Case{"\"depth_mm\": 18.9", "\"depth_mm\": \"x\"", "vertebrae[2].depth_mm"}}) {
    std::string text = good;
    const auto pos = text.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.from;
    text.replace(pos, c.from.size(), c.to);
    auto r = parse_subject_json(text, "s.json");
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().message.rfind("s.json: " + c.field, 0), 0u) << r.error().message;
  }
  EXPECT_FALSE(parse_subject_json("{\"vertebrae\": []}", "s.json"));
  EXPECT_FALSE(parse_subject_json("not json", "s.json"));
  auto missing = SpineModel::from_subject_file("/nonexistent/subject.json");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/nonexistent/subject.json"), std::string::npos);
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

TEST(JointStiffness, EveryJointComesFromANamedPublishedSource) {
  const JointStiffnessTable& t = generic_joint_stiffness();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_EQ(t[j].name, fmt::format("{}-{}", kVertebraNames[j], kVertebraNames[j + 1]));
    EXPECT_TRUE(t[j].source == "W" || t[j].source == "Y" || t[j].source == "interpolated") << t[j].source;
  }
  // Yamamoto et al. 1989, L1-2: 4.9° lateral bending at 10 N·m.
  EXPECT_NEAR(t[12].nm_per_rad().x(), 10.0 / (4.9 * M_PI / 180), 1e-9);
  EXPECT_EQ(t[12].source, "Y");
  // Wilke et al. 2017, T1-T2: 14° flexion + extension at ±7.5 N·m.
  EXPECT_NEAR(t[0].nm_per_rad().z(), 7.5 / (7.0 * M_PI / 180), 1e-9);
}

TEST(JointStiffness, BadFilesNameFileLineAndKey) {
  std::string text(joint_stiffness_toml());
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return parse_joint_stiffness(t, "stiff.toml");
  };
  auto unknown = with("source = \"W\"", "source = \"W\"\nstiffness = 3.0");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("stiff.toml:"), std::string::npos) << unknown.error().message;
  EXPECT_NE(unknown.error().message.find("joint[0].stiffness: unknown key"), std::string::npos)
      << unknown.error().message;
  auto unsourced = with("source = \"W\"", "");
  ASSERT_FALSE(unsourced);
  EXPECT_NE(unsourced.error().message.find("joint[0].source"), std::string::npos) << unsourced.error().message;
  auto misnamed = with("name = \"T2-T3\"", "name = \"T3-T2\"");
  ASSERT_FALSE(misnamed);
  EXPECT_NE(misnamed.error().message.find("joint[1].name: expected \"T2-T3\""), std::string::npos)
      << misnamed.error().message;
  auto negative = with("lateral_deg = 4.9", "lateral_deg = -4.9");
  ASSERT_FALSE(negative);
  EXPECT_NE(negative.error().message.find("joint[12].lateral_deg"), std::string::npos) << negative.error().message;
}

TEST(JointStiffness, TheTableDecidesHowABendSharesOut) {
  // The same lateral bend of the ends, once with the shipped table and once
  // with the lumbar joints four times softer laterally: the soft lumbar
  // joints take a larger part of the bend.
  const auto subject = test::make_subject(1750, 1.0);
  const Posture bent = test::truth_posture(subject, 0, 20, 0, 0);
  auto lumbar_lateral = [&](const JointStiffnessTable& table) {
    SpineModelOptions o;
    o.voxel_mm = 2.0;
    o.stiffness = table;
    const SpineModel model = SpineModel::from_subject(subject.spine, o);
    SpineDynamics dyn(model);
    EXPECT_TRUE(dyn.settle(*targets_of(bent)).converged);
    const auto angles = intervertebral_angles(dyn.pose());
    double sum = 0;
    for (std::size_t j = 12; j < kJointCount; ++j) sum += std::abs(angles[j].lateral);
    return sum;
  };
  JointStiffnessTable soft = generic_joint_stiffness();
  for (std::size_t j = 12; j < kJointCount; ++j) soft[j].lateral_deg *= 4;
  const double shipped = lumbar_lateral(generic_joint_stiffness());
  EXPECT_GT(lumbar_lateral(soft), shipped + 2.0) << shipped;
}

}  // namespace
}  // namespace spinewatch

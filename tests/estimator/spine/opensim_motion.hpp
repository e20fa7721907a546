#pragma once
// A second, independent description of how a whole-trunk bend shares out
// over the levels: the coordinate-coupling ratios of published OpenSim
// models. The accurate model's stiffness is built from the range-of-motion
// literature (Wilke 2017 in vitro, Pearcy 1985 in vivo; config/
// spine-generic.toml); the phantom's own motion (distribute()) comes from
// the same table. These ratios come from neither, so a Table-1 run posed
// with them measures the model on a motion it was not built from.
//
// Sources (figures transcribed, no code copied):
//  [Ch] Christophy M, Faruk Senan NA, Lotz JC, O'Reilly OM (2012), "A
//       musculoskeletal model for the lumbar spine", Biomech Model
//       Mechanobiol 11:19–34: CoordinateCouplerConstraint coefficients of
//       its lumbar joints on the flex_extension / lat_bending /
//       axial_rotation coordinates, with the axial coefficients as updated
//       by the model's authors on its SimTK forum ("Axial rotation
//       coordinate coupling coefficients update"). Read from
//       github.com/mjhmilla/kinematicPassengerModel,
//       models/Christophy2012_axialRotationUpd_skeletonOnly.osim.
//  [IB] The IBHGC (Arts et Métiers) EOS-personalised thoracolumbar OpenSim
//       model: the thoracic coupling coefficients on its T12-L1 coordinates
//       and the ranges of its thoracic and lumbar coordinates. Read from
//       github.com/SamuelHybois/ibhgc_OpenSim, personnalisation/
//       test_perso_YP.m ("Repartition de la rotation dans les vertebres
//       thoraciques"; the file names no source for the ratios). It uses
//       [Ch] for the lumbar levels, as we do.
#include <array>
#include <cmath>
#include <vector>

#include "spine_truth.hpp"

namespace spinewatch::test {

struct CouplingShare {
  double flexion, lateral, axial;  // fraction of its region's coordinate
};

// T1-T2 … T12-L1: fraction of the thoracic coordinate [IB] (flexion and
// lateral bending share one set of ratios there).
inline constexpr std::array<CouplingShare, 12> kOpenSimThoracic{{
    {0.3592, 0.3592, 0.2515},  // T1-T2
    {0.1372, 0.1372, 0.1600},  // T2-T3
    {0.0529, 0.0529, 0.0926},  // T3-T4
    {0.0461, 0.0461, 0.0806},  // T4-T5
    {0.0350, 0.0350, 0.0599},  // T5-T6
    {0.0383, 0.0383, 0.0645},  // T6-T7
    {0.0387, 0.0387, 0.0665},  // T7-T8
    {0.0412, 0.0412, 0.0512},  // T8-T9
    {0.0494, 0.0494, 0.0461},  // T9-T10
    {0.0674, 0.0674, 0.0503},  // T10-T11
    {0.0674, 0.0674, 0.0419},  // T11-T12
    {0.0674, 0.0674, 0.0349},  // T12-L1
}};

// L1-L2 … L4-L5: fraction of the lumbar coordinate [Ch]. L5-S1 takes the
// rest (0.125, 0.1356, 0.2078); it lies below the waist vertebra, which the
// Table-1 protocol gives, so it is not part of our chain.
inline constexpr std::array<CouplingShare, 4> kOpenSimLumbar{{
    {0.255, 0.188, 0.168831},  // L1-L2
    {0.231, 0.2501, 0.181818},  // L2-L3
    {0.204, 0.2453, 0.220779},  // L3-L4
    {0.185, 0.1811, 0.220779},  // L4-L5
}};

// How a whole-trunk angle splits between the thoracic and the lumbar
// coordinate: in proportion to their full ranges in [IB] (thoracic F+E
// −30…+40°, lateral ±30°, axial ±30°; lumbar F+E ±44.7°, lateral ±20°,
// axial ±12.5°), i.e. both reach their limits together.
inline constexpr CouplingShare kThoracicRange{70.0, 60.0, 60.0};
inline constexpr CouplingShare kLumbarRange{89.4, 40.0, 25.0};

// Joint angles for a whole-trunk (T1 relative to L5) flexion, lateral bend
// and twist, degrees, shared out as the OpenSim description does.
inline SegmentalMotion opensim_motion(double flexion_deg, double lateral_deg, double twist_deg) {
  auto component = [](double total, double CouplingShare::*which) {
    std::array<double, kJointCount> share{};
    const double t = kThoracicRange.*which, l = kLumbarRange.*which;
    double chain = 0;
    for (std::size_t j = 0; j < 12; ++j) chain += (share[j] = t * (kOpenSimThoracic[j].*which));
    for (std::size_t j = 0; j < 4; ++j) chain += (share[12 + j] = l * (kOpenSimLumbar[j].*which));
    for (double& s : share) s *= total / chain;
    return share;
  };
  const auto f = component(flexion_deg, &CouplingShare::flexion);
  const auto b = component(lateral_deg, &CouplingShare::lateral);
  const auto a = component(twist_deg, &CouplingShare::axial);
  SegmentalMotion m;
  for (std::size_t j = 0; j < kJointCount; ++j) m.joints[j] = {f[j], b[j], a[j]};
  return m;
}

// The subject's neutral spine posed by the OpenSim shares, each joint's
// share varied by the subject's factor as the phantom-motion truth does.
inline Posture opensim_posture(const TruthSubject& s, double flexion_deg, double lateral_deg, double twist_deg,
                               std::uint64_t seq) {
  SegmentalMotion m = opensim_motion(flexion_deg, lateral_deg, twist_deg);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    m.joints[j].flexion *= s.joint_factor[j];
    m.joints[j].lateral *= s.joint_factor[j];
    m.joints[j].twist *= s.joint_factor[j];
  }
  return posture_of(s, m, seq);
}

}  // namespace spinewatch::test

#include "spinewatch/export/opensim_files.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/vertebra_levels.hpp"

namespace spinewatch::exporting {
namespace {

// Root to tip, as OpenSim models list coordinates: L5 in the world (its
// neutral orientation is the world's, docs/interfaces.md §1), then each joint
// from the lowest: joint i is vertebra i relative to vertebra i + 1.
std::vector<std::string> joint_names() {
  std::vector<std::string> names{std::string(kVertebraNames[kWaistIndex])};
  for (std::size_t i = kJointCount; i-- > 0;)
    names.push_back(fmt::format("{}_{}", kVertebraNames[i], kVertebraNames[i + 1]));
  return names;
}

std::vector<JointAngles> angles_root_to_tip(const SpinePose& pose) {
  std::vector<JointAngles> out{joint_angles(pose[kWaistIndex].q)};
  const auto joints = intervertebral_angles(pose);
  for (std::size_t i = kJointCount; i-- > 0;) out.push_back(joints[i]);
  return out;
}

// A value that rounds to zero at 4 decimals is written "0.0000", not "-0.0000".
double unsigned_zero(double deg) { return std::abs(deg) < 0.5e-4 ? 0.0 : deg; }

}  // namespace

std::vector<std::string> mot_columns() {
  std::vector<std::string> columns;
  for (const std::string& j : joint_names())
    for (const char* axis : {"flex", "lat", "rot"}) columns.push_back(j + "_" + axis);
  return columns;
}

double row_rate_hz(const std::vector<PoseRow>& rows) {
  if (rows.size() < 2) return 0;
  std::vector<std::int64_t> steps;
  for (std::size_t i = 1; i < rows.size(); ++i) steps.push_back(rows[i].t_ns - rows[i - 1].t_ns);
  std::nth_element(steps.begin(), steps.begin() + std::ptrdiff_t(steps.size() / 2), steps.end());
  const std::int64_t median = steps[steps.size() / 2];
  return median > 0 ? 1e9 / double(median) : 0;
}

std::string mot_text(const std::vector<PoseRow>& rows, std::string_view name) {
  const auto columns = mot_columns();
  std::string out = fmt::format("{}\nversion=1\nnRows={}\nnColumns={}\ninDegrees=yes\nendheader\ntime", name,
                                rows.size(), columns.size() + 1);
  for (const auto& c : columns) out += "\t" + c;
  out += "\n";
  for (const PoseRow& r : rows) {
    out += fmt::format("{:.6f}", double(r.t_ns) / 1e9);
    for (const JointAngles& a : angles_root_to_tip(r.pose))
      out += fmt::format("\t{:.4f}\t{:.4f}\t{:.4f}", unsigned_zero(a.flexion), unsigned_zero(a.lateral),
                         unsigned_zero(a.twist));
    out += "\n";
  }
  return out;
}

std::string trc_text(const std::vector<PoseRow>& rows, std::string_view file_name) {
  const double rate = row_rate_hz(rows);
  std::string out = fmt::format("PathFileType\t4\t(X/Y/Z)\t{}\n", file_name);
  out += "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n";
  out += fmt::format("{:.3f}\t{:.3f}\t{}\t{}\tmm\t{:.3f}\t1\t{}\n", rate, rate, rows.size(), kVertebraCount, rate,
                     rows.size());
  out += "Frame#\tTime";
  for (std::size_t v = 0; v < kVertebraCount; ++v) out += fmt::format("\t{}\t\t", kVertebraNames[v]);
  out += "\n\t";
  for (std::size_t v = 0; v < kVertebraCount; ++v) out += fmt::format("\tX{0}\tY{0}\tZ{0}", v + 1);
  out += "\n\n";
  std::size_t frame = 0;
  for (const PoseRow& r : rows) {
    out += fmt::format("{}\t{:.6f}", ++frame, double(r.t_ns) / 1e9);
    for (const VertebraPose& v : r.pose)
      out += fmt::format("\t{:.3f}\t{:.3f}\t{:.3f}", v.body_center.x(), v.body_center.y(), v.body_center.z());
    out += "\n";
  }
  return out;
}

}  // namespace spinewatch::exporting

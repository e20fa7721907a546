#include "spinewatch/replay/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {

ErrorStats summarise(std::vector<double> values) {
  ErrorStats s;
  s.count = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / double(values.size());
  // Nearest-rank percentile.
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * double(values.size())));
  s.p95 = values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
  s.max = values.back();
  return s;
}

namespace {

double t1_l5_twist_deg(const SpinePose& p) {
  const Eigen::Quaterniond rel = p[kWaistIndex].q.conjugate() * p[kNeckIndex].q;
  return 2.0 * std::atan2(rel.y(), rel.w()) * 180.0 / M_PI;
}

void add_angle(std::vector<double>& errors, TrunkAngleScore& score, double published, double truth) {
  errors.push_back(std::abs(published - truth));
  if (std::abs(truth) < kTrunkBentDeg) return;
  ++score.bent_frames;
  score.wrong_side += published * truth < 0;
}

}  // namespace

Evaluation evaluate(const std::vector<Posture>& estimate, const std::vector<Posture>& truth, bool include_init) {
  std::map<std::uint64_t, const Posture*> by_seq;
  for (const auto& p : estimate) by_seq[p.seq] = &p;

  Evaluation e;
  std::vector<double> neck, waist, all, twist, inclination, side_bend;
  std::array<std::vector<double>, 3> neck_axis, waist_axis;
  std::array<std::vector<double>, kVertebraCount> level;
  std::array<std::array<std::vector<double>, 3>, kVertebraCount> level_axis;

  for (const auto& t : truth) {
    if (t.state == TrackingState::Lost || !t.neck || !t.waist || !t.vertebrae) continue;
    ++e.truth_frames;
    auto it = by_seq.find(t.seq);
    const Posture* p = it == by_seq.end() ? nullptr : it->second;
    if (p && p->state == TrackingState::Init && !include_init) {
      ++e.init_frames;
      continue;
    }
    if (!p || p->state == TrackingState::Lost || !p->neck || !p->waist) {
      ++e.lost_frames;
      e.lost_seqs.push_back(t.seq);
      continue;
    }
    ++e.estimated_frames;
    const Eigen::Vector3d dn = *p->neck - *t.neck, dw = *p->waist - *t.waist;
    neck.push_back(dn.norm());
    waist.push_back(dw.norm());
    for (int a = 0; a < 3; ++a) {
      neck_axis[a].push_back(std::abs(dn[a]));
      waist_axis[a].push_back(std::abs(dw[a]));
    }
    if (p->vertebrae) {
      const double true_twist = t1_l5_twist_deg(*t.vertebrae), published = t1_l5_twist_deg(*p->vertebrae);
      twist.push_back(std::abs(published - true_twist));
      const bool unresolved = p->fit.flag == kTwistUnresolvedFlag;
      e.twist_unresolved_frames += unresolved;
      if (std::abs(true_twist) >= 15) {
        ++e.twisted_frames;
        e.twisted_published_untwisted += !unresolved && std::abs(published) <= 10;
      }
      const Eigen::Vector3d facing = facing_of(*t.vertebrae);
      const TrunkTilt true_tilt = trunk_tilt(*t.vertebrae, facing), tilt = trunk_tilt(*p->vertebrae, facing);
      add_angle(inclination, e.inclination, tilt.inclination_deg, true_tilt.inclination_deg);
      add_angle(side_bend, e.side_bend, tilt.side_bend_deg, true_tilt.side_bend_deg);
      for (std::size_t i = 0; i < kVertebraCount; ++i) {
        const Eigen::Vector3d d = (*p->vertebrae)[i].body_center - (*t.vertebrae)[i].body_center;
        level[i].push_back(d.norm());
        all.push_back(d.norm());
        for (int a = 0; a < 3; ++a) level_axis[i][a].push_back(std::abs(d[a]));
      }
    }
  }
  e.neck = summarise(neck);
  e.waist = summarise(waist);
  e.all_vertebrae = summarise(all);
  e.twist = summarise(twist);
  e.inclination.error = summarise(inclination);
  e.side_bend.error = summarise(side_bend);
  for (int a = 0; a < 3; ++a) {
    e.neck_axis[a] = summarise(neck_axis[a]);
    e.waist_axis[a] = summarise(waist_axis[a]);
  }
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    e.per_level[i] = summarise(level[i]);
    for (int a = 0; a < 3; ++a) e.per_level_axis[i][a] = summarise(level_axis[i][a]);
  }
  return e;
}

std::string format_evaluation(const Evaluation& e) {
  std::string out;
  auto line = [&out](std::string_view name, const ErrorStats& s) {
    out += fmt::format("  {:<10} {:>8.1f} {:>8.1f} {:>8.1f}\n", name, s.mean, s.p95, s.max);
  };
  out += fmt::format("frames with a true posture: {}, estimated: {}, lost: {}, initialising: {}\n",
                     e.truth_frames, e.estimated_frames, e.lost_frames, e.init_frames);
  out += "errors in mm      mean      p95      max\n";
  line("neck", e.neck);
  line("waist", e.waist);
  line("vertebrae", e.all_vertebrae);
  out += fmt::format("  {:<10} {:>8.1f} {:>8.1f} {:>8.1f}   (T1 vs L5 axial twist, degrees)\n", "twist", e.twist.mean,
                     e.twist.p95, e.twist.max);
  out += fmt::format("true twist 15 deg or more: {} frames, {} published within 10 deg unflagged; {} frames flagged twist_unresolved\n",
                     e.twisted_frames, e.twisted_published_untwisted, e.twist_unresolved_frames);
  for (auto [name, a] : {std::pair{"inclination", &e.inclination}, std::pair{"side bend", &e.side_bend}})
    out += fmt::format("  {:<11} {:>7.1f} {:>8.1f} {:>8.1f}   (trunk, degrees); true {:.0f} deg or more: {} frames, {} "
                       "on the wrong side\n",
                       name, a->error.mean, a->error.p95, a->error.max, kTrunkBentDeg, a->bent_frames, a->wrong_side);
  const char* axes[] = {"x (ant)", "y (sup)", "z (right)"};
  out += "per axis |Δ|     neck mean/p95      waist mean/p95\n";
  for (int a = 0; a < 3; ++a)
    out += fmt::format("  {:<10} {:>7.1f} {:>7.1f}    {:>7.1f} {:>7.1f}\n", axes[a], e.neck_axis[a].mean,
                       e.neck_axis[a].p95, e.waist_axis[a].mean, e.waist_axis[a].p95);
  if (e.all_vertebrae.count > 0) {
    out += "per level        3D mean   p95    max   |Δx| |Δy| |Δz| mean\n";
    for (std::size_t i = 0; i < kVertebraCount; ++i) {
      const auto& s = e.per_level[i];
      const auto& ax = e.per_level_axis[i];
      out += fmt::format("  {:<10} {:>7.1f} {:>6.1f} {:>6.1f}   {:>4.1f} {:>4.1f} {:>4.1f}\n", kVertebraNames[i], s.mean,
                         s.p95, s.max, ax[0].mean, ax[1].mean, ax[2].mean);
    }
  }
  if (!e.lost_seqs.empty()) {
    out += "lost seq:";
    for (std::size_t i = 0; i < e.lost_seqs.size() && i < 40; ++i) out += fmt::format(" {}", e.lost_seqs[i]);
    if (e.lost_seqs.size() > 40) out += " …";
    out += "\n";
  }
  return out;
}

}  // namespace spinewatch

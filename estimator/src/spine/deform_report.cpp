#include "spinewatch/estimator/spine/deform_report.hpp"

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

namespace spinewatch {
namespace {

struct Accumulator {
  double sum = 0, max = 0;
  std::size_t n = 0;
  void add(double v) {
    v = std::abs(v);
    sum += v;
    max = std::max(max, v);
    ++n;
  }
  AxisError result() const { return {n ? sum / double(n) : 0.0, max}; }
};

bool distinct_seqs(const std::vector<Posture>& s) {
  std::set<std::uint64_t> seen;
  for (const auto& p : s)
    if (!seen.insert(p.seq).second) return false;
  return true;
}

}  // namespace

DeformReport compare_deformation(const std::vector<Posture>& estimated, const std::vector<Posture>& truth) {
  std::vector<std::pair<const Posture*, const Posture*>> pairs;
  if (distinct_seqs(estimated) && distinct_seqs(truth)) {
    std::map<std::uint64_t, const Posture*> by_seq;
    for (const auto& t : truth) by_seq[t.seq] = &t;
    for (const auto& e : estimated)
      if (auto it = by_seq.find(e.seq); it != by_seq.end()) pairs.emplace_back(&e, it->second);
  } else {
    for (std::size_t i = 0; i < std::min(estimated.size(), truth.size()); ++i) pairs.emplace_back(&estimated[i], &truth[i]);
  }

  std::array<std::array<Accumulator, 4>, kVertebraCount> acc{};
  Accumulator overall;
  DeformReport report;
  for (const auto& [e, t] : pairs) {
    if (!e->vertebrae || !t->vertebrae) {
      ++report.skipped;
      continue;
    }
    ++report.frames;
    for (std::size_t i = 0; i < kVertebraCount; ++i) {
      const Eigen::Vector3d d = (*e->vertebrae)[i].body_center - (*t->vertebrae)[i].body_center;
      acc[i][0].add(d.z());
      acc[i][1].add(d.y());
      acc[i][2].add(d.x());
      acc[i][3].add(d.norm());
      overall.add(d.norm());
    }
  }
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    LevelError& l = report.levels[i];
    l.level = std::string(kVertebraNames[i]);
    l.lateral = acc[i][0].result();
    l.vertical = acc[i][1].result();
    l.anterior = acc[i][2].result();
    l.distance = acc[i][3].result();
  }
  report.overall = overall.result();
  return report;
}

std::string format_table(const DeformReport& r) {
  std::string out = fmt::format("Deformation error against ground truth, mm ({} frames", r.frames);
  if (r.skipped) out += fmt::format(", {} skipped without vertebrae", r.skipped);
  out += ")\n";
  out += fmt::format("{:<6}{:>16}{:>16}{:>16}{:>16}\n", "level", "|dZ| lateral", "|dY| vertical", "|dX| anterior",
                     "distance");
  out += fmt::format("{:<6}{:>16}{:>16}{:>16}{:>16}\n", "", "mean / max", "mean / max", "mean / max", "mean / max");
  auto cell = [](const AxisError& a) { return fmt::format("{:.2f} / {:.2f}", a.mean, a.max); };
  for (const auto& l : r.levels)
    out += fmt::format("{:<6}{:>16}{:>16}{:>16}{:>16}\n", l.level, cell(l.lateral), cell(l.vertical), cell(l.anterior),
                       cell(l.distance));
  out += fmt::format("{:<6}{:>64}\n", "all", cell(r.overall));
  return out;
}

}  // namespace spinewatch

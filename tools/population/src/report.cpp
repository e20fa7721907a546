#include "spinewatch/population/report.hpp"

#include <fmt/format.h>

namespace spinewatch::population {
namespace {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / double(v.size());
}

}  // namespace

std::string format_runs(const std::vector<Run>& runs) {
  std::string out =
      "| subject | sex | stature | BMI | scenario | model height | tracking / pairs | lost | neck | waist | vertebrae |\n"
      "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|\n";
  for (const Run& r : runs) {
    std::vector<double> all;
    for (const auto& level : r.delta)
      for (const auto& d : level) all.push_back(d.norm());
    out += fmt::format("| {} | {} | {:.0f} | {:.1f} | {} | {:.0f} | {} / {} | {} | {:.1f} | {:.1f} | {:.1f} |\n",
                       r.subject_id, anthropometry::to_string(r.sex), r.stature_mm, r.bmi, r.scenario,
                       r.model_height_mm, r.tracking, r.frames, r.lost, mean(r.neck), mean(r.waist), mean(all));
  }
  return out;
}

std::string format_pooled(const Pooled& p, std::string_view title) {
  std::string out = fmt::format("{}: {} runs, {} pairs with the subject, {} tracking, {} init, {} lost\n\n", title,
                                p.runs, p.frames, p.tracking, p.init, p.lost);
  out += "| | mean | p95 | max |\n|---|---:|---:|---:|\n";
  for (auto [name, s] : {std::pair{"neck (T1)", &p.neck}, std::pair{"waist (L5)", &p.waist},
                         std::pair{"every vertebra", &p.vertebrae}, std::pair{"stature |error|", &p.stature_abs}})
    out += fmt::format("| {} | {:.1f} | {:.1f} | {:.1f} |\n", name, s->mean, s->p95, s->max);
  out += fmt::format("\nstature bias (model − measured, standing runs): {:+.1f} mm\n\n", p.stature_bias);
  out += "| level | 3D mean | p95 | bias anterior (x) | bias vertical (y) | bias lateral (z) |\n"
         "|---|---:|---:|---:|---:|---:|\n";
  for (std::size_t k = 0; k < kVertebraCount; ++k)
    out += fmt::format("| {} | {:.1f} | {:.1f} | {:+.1f} | {:+.1f} | {:+.1f} |\n", kVertebraNames[k], p.per_level[k].mean,
                       p.per_level[k].p95, p.bias[k].x(), p.bias[k].y(), p.bias[k].z());
  return out;
}

}  // namespace spinewatch::population

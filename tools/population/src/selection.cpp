#include "spinewatch/population/selection.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch::population {

using anthropometry::AnsurSubject;
using anthropometry::Sex;

double bmi(const AnsurSubject& s) {
  const double m = s.stature_mm / 1000.0;
  return m > 0 ? s.mass_kg / (m * m) : 0;
}

namespace {

double percentile(std::vector<double> v, double pct) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(pct / 100.0 * double(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

std::vector<AnsurSubject> spread(const std::vector<AnsurSubject>& all, Sex sex, int count, const SelectionOptions& o) {
  std::vector<double> statures;
  for (const auto& s : all)
    if (s.sex == sex) statures.push_back(s.stature_mm);
  const double lo = percentile(statures, o.stature_lo_pct), hi = percentile(statures, o.stature_hi_pct);
  std::vector<AnsurSubject> eligible;
  for (const auto& s : all)
    if (s.sex == sex && anthropometry::partition_of(s.id) == o.set && s.stature_mm >= lo && s.stature_mm <= hi &&
        bmi(s) >= o.bmi_min && bmi(s) <= o.bmi_max)
      eligible.push_back(s);
  std::stable_sort(eligible.begin(), eligible.end(), [](const AnsurSubject& a, const AnsurSubject& b) {
    return a.stature_mm != b.stature_mm ? a.stature_mm < b.stature_mm : a.id < b.id;
  });
  std::vector<AnsurSubject> out;
  if (eligible.empty() || count <= 0) return out;
  for (int i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>((i + 0.5) / count * double(eligible.size()));
    out.push_back(eligible[std::min(k, eligible.size() - 1)]);
  }
  return out;
}

}  // namespace

std::vector<AnsurSubject> select_subjects(const std::vector<AnsurSubject>& all, const SelectionOptions& options) {
  std::vector<AnsurSubject> out = spread(all, Sex::Male, options.men, options);
  for (auto& s : spread(all, Sex::Female, options.women, options)) out.push_back(std::move(s));
  return out;
}

}  // namespace spinewatch::population

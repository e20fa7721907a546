#pragma once
// Which measured adults a population sweep runs: people of one set of the
// fixed train/test split (anthropometry/split.hpp), both sexes, spread
// evenly over each sex's 5th–95th stature percentiles, within a BMI
// range. The choice depends on the data and the counts alone, so a sweep
// and its test run the same people on every machine.
#include <vector>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/anthropometry/split.hpp"

namespace spinewatch::population {

struct SelectionOptions {
  anthropometry::Partition set = anthropometry::Partition::Test;
  int men = 20, women = 20;
  double bmi_min = 18, bmi_max = 38;
  double stature_lo_pct = 5, stature_hi_pct = 95;  // percentiles of the sex in the whole release
};

double bmi(const anthropometry::AnsurSubject& s);

// Men first, then women, each by rising stature: the subjects at the
// middles of `men` (`women`) equal stature-rank bands of the eligible
// people of the set.
std::vector<anthropometry::AnsurSubject> select_subjects(const std::vector<anthropometry::AnsurSubject>& all,
                                                         const SelectionOptions& options);

}  // namespace spinewatch::population

#pragma once
// The fixed split of ANSUR II into people the regressions are fitted on
// and people they are tested on (docs/anthropometry.md). The rule depends
// on the SubjectId alone, so a subject is in the same set in every tool,
// on every machine and in any subset of the release:
//
//   test  ⇔  splitmix64(SubjectId) mod 10 < 3      (about 30 %)
//
// where splitmix64 is the finaliser of Steele et al.'s SplitMix64
// generator (a bijective 64-bit mix), so neighbouring ids, which ANSUR
// gives to people measured on the same day, are scattered over both sets.
#include <cstdint>
#include <string_view>
#include <vector>

#include "spinewatch/anthropometry/ansur.hpp"

namespace spinewatch::anthropometry {

enum class Partition : std::uint8_t { Train, Test };
std::string_view to_string(Partition partition);

std::uint64_t splitmix64(std::uint64_t x);
Partition partition_of(int subject_id);

// The subjects of one set, in their order in `subjects`.
std::vector<AnsurSubject> subjects_in(const std::vector<AnsurSubject>& subjects, Partition partition);

}  // namespace spinewatch::anthropometry

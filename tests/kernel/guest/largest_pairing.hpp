#pragma once
// How many pairs two free-running streams' timestamps allow: the largest
// one-to-one pairing within a tolerance. Counting every frontal frame with
// any lateral frame in reach overcounts when the cameras run about half a
// period apart (one lateral frame is then in reach of two frontal ones).
// Walking both sorted streams from the front finds the maximum: a head pair
// in reach belongs to some largest pairing, and a head too old for the other
// stream's head is too old for everything after it.
// (FreeRunPairer.CamerasHalfAPeriodApart… checks the pairer against a
// maximum matching found by augmenting paths.)
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace spinewatch::kernel_test {

inline std::size_t largest_pairing(const std::vector<std::int64_t>& frontal_ns,
                                   const std::vector<std::int64_t>& lateral_ns, std::int64_t tolerance_ns) {
  std::size_t pairs = 0;
  for (std::size_t f = 0, l = 0; f < frontal_ns.size() && l < lateral_ns.size();) {
    const std::int64_t d = frontal_ns[f] - lateral_ns[l];
    if (std::llabs(d) <= tolerance_ns) {
      ++pairs;
      ++f;
      ++l;
    } else if (d < 0) {
      ++f;
    } else {
      ++l;
    }
  }
  return pairs;
}

}  // namespace spinewatch::kernel_test

// The test helpers' own logic: the sanitizer build's sample of a sweep
// (test::sanitizer_sample), which decides what that stage checks.
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace spinewatch {
namespace {

std::vector<int> cases(int n) {
  std::vector<int> v(static_cast<std::size_t>(n));
  std::iota(v.begin(), v.end(), 0);
  return v;
}

TEST(SanitizerSample, EveryCaseInReleaseEveryStrideThUnderTheSanitizers) {
  const auto kept = test::sanitizer_sample(cases(10), 3);
  if (test::kSanitized)
    EXPECT_EQ(kept, (std::vector<int>{0, 3, 6, 9}));
  else
    EXPECT_EQ(kept, cases(10));
}

TEST(SanitizerSample, NeverEmptyAndAStrideOfZeroOrOneKeepsEveryCase) {
  EXPECT_EQ(test::sanitizer_sample(cases(2), 5), (test::kSanitized ? std::vector<int>{0} : cases(2)));
  EXPECT_EQ(test::sanitizer_sample(cases(4), 0), cases(4));
  EXPECT_EQ(test::sanitizer_sample(cases(4), 1), cases(4));
  EXPECT_TRUE(test::sanitizer_sample(cases(0), 3).empty());
}

}  // namespace
}  // namespace spinewatch

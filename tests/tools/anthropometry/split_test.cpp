#include <gtest/gtest.h>

#include "spinewatch/anthropometry/split.hpp"
#include "test_support.hpp"

namespace spinewatch::anthropometry {
namespace {

TEST(AnsurSplit, RuleIsFixedByTheId) {
  // splitmix64 reference values (Vigna's splitmix64.c with state = x).
  EXPECT_EQ(splitmix64(0), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(partition_of(10027), partition_of(10027));
  std::size_t test = 0;
  for (int id = 1; id <= 100000; ++id) test += partition_of(id) == Partition::Test;
  EXPECT_NEAR(double(test) / 100000.0, 0.3, 0.01);
}

TEST(AnsurSplit, BothSexesInBothSetsOfTheRelease) {
  auto subjects = read_ansur(test::source_path(std::string(kAnsurRelativeDir)));
  ASSERT_TRUE(subjects) << subjects.error().message;
  for (Partition p : {Partition::Train, Partition::Test}) {
    const auto set = subjects_in(*subjects, p);
    std::size_t men = 0, women = 0;
    for (const AnsurSubject& s : set) (s.sex == Sex::Male ? men : women)++;
    const double share = p == Partition::Test ? 0.3 : 0.7;
    EXPECT_NEAR(double(men), share * 4082, 0.05 * 4082) << to_string(p);
    EXPECT_NEAR(double(women), share * 1986, 0.05 * 1986) << to_string(p);
  }
}

}  // namespace
}  // namespace spinewatch::anthropometry

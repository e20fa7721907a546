// kernel_guest_test: GoogleTest inside the QEMU guest. Besides GoogleTest's
// own output, every test ends with one machine-readable line on standard
// output (the serial console), which tests/kernel/kernel-vm turns into one
// CTest result:  @@SW-RESULT <Suite.Name> PASS|FAIL|SKIP <reason>
#include <time.h>

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "guest_env.hpp"

namespace spinewatch::kernel_test {

namespace {

// One line, bounded: the host parses line by line.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  constexpr std::size_t kMax = 400;
  if (text.size() > kMax) text = text.substr(0, kMax) + "...";
  return text;
}

class ResultLinePrinter : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo& info) override {
    const ::testing::TestResult& result = *info.result();
    const char* verdict = "PASS";
    std::string reason;
    if (result.Skipped()) {
      verdict = "SKIP";
    } else if (result.Failed()) {
      verdict = "FAIL";
    }
    for (int i = 0; i < result.total_part_count(); ++i) {
      const auto& part = result.GetTestPartResult(i);
      if (part.failed() || part.skipped()) {
        reason = part.message();
        if (part.failed() && part.file_name()) {
          reason = std::string(part.file_name()) + ":" + std::to_string(part.line_number()) + ": " + reason;
        }
        break;
      }
    }
    std::printf("\n@@SW-RESULT %s.%s %s %s\n", info.test_suite_name(), info.name(), verdict,
                one_line(reason).c_str());
    std::fflush(stdout);
  }
};

}  // namespace
}  // namespace spinewatch::kernel_test

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(new spinewatch::kernel_test::ResultLinePrinter);
  return RUN_ALL_TESTS();
}

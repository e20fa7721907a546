// The unit file, checked by systemd's own tools. Where this machine cannot
// run them, the tests say so with GTEST_SKIP (never a silent pass).
#include <gtest/gtest.h>

#include <regex>

#include "test_support.hpp"

namespace spinewatch {
namespace {

const char* kUnit = SPINEWATCH_TEST_UNIT;  // the unit with ExecStart= pointing at the built spinewatchd

bool have_systemd_analyze() { return test::run_command("command -v systemd-analyze").exit_code == 0; }

// Failures that are about the machine, not the unit.
bool environmental(const std::string& output) {
  static const std::regex pattern(
      "System has not been booted with systemd|Failed to connect to bus|Failed to initialize manager|"
      "Unknown option|unrecognized option|Operation not permitted|Failed to create /init.scope",
      std::regex::icase);
  return std::regex_search(output, pattern);
}

TEST(SystemdUnit, VerifiesClean) {
  if (!have_systemd_analyze()) GTEST_SKIP() << "systemd-analyze is not installed";
  ASSERT_TRUE(std::filesystem::exists(kUnit)) << kUnit;
  const auto r = test::run_command(std::string("systemd-analyze verify '") + kUnit + "'");
  if (r.exit_code != 0 && environmental(r.output)) GTEST_SKIP() << "systemd-analyze verify cannot run here: " << r.output;
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // Warnings about our unit come out with exit code 0 too.
  EXPECT_EQ(r.output.find("spinewatch.service:"), std::string::npos) << r.output;
}

TEST(SystemdUnit, SecurityExposureAtMostTwoAndAHalf) {
  if (!have_systemd_analyze()) GTEST_SKIP() << "systemd-analyze is not installed";
  const auto r = test::run_command(std::string("systemd-analyze security --offline=yes --no-pager '") + kUnit + "'");
  if (r.exit_code != 0 && environmental(r.output))
    GTEST_SKIP() << "systemd-analyze security --offline cannot run here: " << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(Overall exposure level for \S+: ([0-9.]+))"))) << r.output;
  const double exposure = std::stod(m[1]);
  RecordProperty("exposure", m[1].str());
  std::printf("systemd-analyze security exposure: %.1f\n", exposure);
  EXPECT_LE(exposure, 2.5) << r.output;
}

TEST(SystemdUnit, HasTheRequiredSettings) {
  const std::string unit = test::read_file(kUnit);
  for (const char* line : {"Type=notify", "Restart=on-failure", "DynamicUser=yes", "SupplementaryGroups=video gpio",
                           "DevicePolicy=closed", "DeviceAllow=char-video4linux rw", "DeviceAllow=char-gpiochip rw",
                           "RuntimeDirectory=spinewatch", "ProtectSystem=strict", "ProtectHome=yes",
                           "NoNewPrivileges=yes", "RestrictAddressFamilies=AF_UNIX AF_INET AF_INET6",
                           "SystemCallFilter=@system-service"})
    EXPECT_NE(unit.find(std::string("\n") + line + "\n"), std::string::npos) << "missing: " << line;
  EXPECT_TRUE(std::regex_search(unit, std::regex("\nWatchdogSec=[1-9]")));
}

}  // namespace
}  // namespace spinewatch

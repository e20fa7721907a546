#include <gtest/gtest.h>

#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(Cli, HelpAndVersionExitZero) {
  auto help = test::run_cli("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("Usage"), std::string::npos);
  auto version = test::run_cli("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("0."), std::string::npos);
}

TEST(Cli, UnknownOptionExitsTwoWithMessage) {
  auto r = test::run_cli("check --frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("frobnicate"), std::string::npos) << r.output;
}

TEST(Cli, BadValueExitsTwo) {
  auto r = test::run_cli("--log-level loud check --config x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("loud"), std::string::npos) << r.output;
}

TEST(Cli, CheckAcceptsTheDefaultConfigAndRejectsBadOnes) {
  auto ok = test::run_cli("check --config " + test::source_path("config/spinewatch.toml").string());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  test::TempDir dir;
  test::write_file(dir / "bad.toml", "[cameras]\nfps = 0\n");
  auto bad = test::run_cli("check --config " + (dir / "bad.toml").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("bad.toml:2: cameras.fps: 0 is out of range"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace spinewatch

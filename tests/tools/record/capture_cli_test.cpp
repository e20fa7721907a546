#include <filesystem>

#include <gtest/gtest.h>

#include "spinewatch/capture/v4l2_probe.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(DevicesCommand, ListsWhatIsPresentOrSaysThereIsNothingAndExitsZero) {
  auto r = test::run_cli("devices");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (list_video_nodes().empty()) {
    EXPECT_NE(r.output.find("No V4L2 video devices (/dev/video*) found."), std::string::npos) << r.output;
  } else {
    EXPECT_NE(r.output.find("V4L2 video devices:"), std::string::npos) << r.output;
  }
  bool any_chip = false;
  for (const auto& e : std::filesystem::directory_iterator("/dev")) {
    if (e.path().filename().string().rfind("gpiochip", 0) == 0) any_chip = true;
  }
  EXPECT_NE(r.output.find(any_chip ? "GPIO chips:" : "No GPIO chips (/dev/gpiochip*) found."), std::string::npos)
      << r.output;
}

TEST(RecordCommand, AMissingCameraIsOneClearMessageAndExitOne) {
  test::TempDir dir;
  const auto out = dir / "rec";
  auto r = test::run_cli("record --out '" + out.string() +
                         "' --frontal /dev/video-spinewatch-none --lateral /dev/video-spinewatch-none2 --frames 3");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("frontal: cannot open /dev/video-spinewatch-none"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(RecordCommand, BadConfigurationIsReportedBeforeAnyDeviceIsOpened) {
  test::TempDir dir;
  test::write_file(dir / "bad.toml", "[cameras]\nfps = \"fast\"\n");
  auto r = test::run_cli("record --out '" + (dir / "rec").string() + "' --config '" + (dir / "bad.toml").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.toml"), std::string::npos) << r.output;
}

TEST(RecordCommand, UsageErrorsExitTwo) {
  EXPECT_EQ(test::run_cli("record --frames 3").exit_code, 2);  // no --out
  EXPECT_EQ(test::run_cli("record --out /tmp/x --frames 3 --seconds 2").exit_code, 2);
  EXPECT_EQ(test::run_cli("record --out /tmp/x --frames 0").exit_code, 2);
}

}  // namespace
}  // namespace spinewatch

#include <gtest/gtest.h>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/capture/v4l2_probe.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(V4l2Probe, ListsIdentityFormatsAndSizes) {
  FakeV4l2Script script;
  script.card = "IMX296 frontal";
  FakeV4l2Device fake(script);
  auto info = probe_v4l2_device(fake, script.path);
  ASSERT_TRUE(info.ok()) << info.error().message;
  EXPECT_EQ(info->driver, "fakecam");
  EXPECT_EQ(info->card, "IMX296 frontal");
  EXPECT_EQ(info->bus, "platform:fakecam");
  EXPECT_TRUE(info->capture);
  EXPECT_TRUE(info->streaming);
  ASSERT_EQ(info->formats.size(), 2u);
  EXPECT_EQ(info->formats[0].fourcc, "YUYV");
  EXPECT_EQ(info->formats[1].fourcc, "GREY");
  EXPECT_EQ(info->formats[0].sizes, (std::vector<std::string>{"320x240", "640x480"}));
  EXPECT_EQ(fake.open_fds(), 0);
}

TEST(V4l2Probe, NamesTheNodeItCannotOpen) {
  FakeV4l2Device fake;
  auto info = probe_v4l2_device(fake, "/dev/video77");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().message.find("/dev/video77: cannot open"), std::string::npos);
}

TEST(V4l2Probe, ListsVideoNodesInNumericOrder) {
  test::TempDir dir;
  for (const char* name : {"video10", "video2", "video0", "videoX", "vide", "video", "media0"}) {
    test::write_file(dir / name, "");
  }
  const auto nodes = list_video_nodes(dir.path());
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_EQ(nodes[0], (dir / "video0").string());
  EXPECT_EQ(nodes[1], (dir / "video2").string());
  EXPECT_EQ(nodes[2], (dir / "video10").string());
}

}  // namespace
}  // namespace spinewatch

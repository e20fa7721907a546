// The libcamera source on a machine without cameras (CI, the build box):
// the camera manager starts and sees none, and opening an id that is not
// there is a clear error, not a crash or a leak. Capture itself needs a
// camera (or vimc under QEMU): see docs/hardware.md.
#include <gtest/gtest.h>

#include "spinewatch/capture/libcamera_camera.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"

namespace spinewatch {
namespace {

#ifdef SPINEWATCH_HAVE_LIBCAMERA

TEST(LibcameraCamera, ManagerStartsAndListsTheCamerasItSees) {
  ASSERT_TRUE(libcamera_built());
  auto cameras = list_libcamera_cameras();
  ASSERT_TRUE(cameras) << cameras.error().message;
  // This machine has none; a developer's may have some: then each has an id.
  for (const auto& c : *cameras) EXPECT_FALSE(c.id.empty());
  // The shared manager stops with its last user and starts again.
  auto again = list_libcamera_cameras();
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(again->size(), cameras->size());
}

TEST(LibcameraCamera, UnknownIdIsAnErrorNamingIt) {
  auto camera = LibcameraCamera::open({.id = "nonexistent", .name = "frontal"});
  ASSERT_FALSE(camera);
  EXPECT_NE(camera.error().message.find("\"nonexistent\""), std::string::npos) << camera.error().message;
  EXPECT_NE(camera.error().message.find("not found"), std::string::npos) << camera.error().message;
}

// The daemon's source: cameras.frontal / lateral are libcamera ids; an id
// that is not there stops the start with the id in the message.
TEST(LibcameraCamera, DaemonSourceNamesTheMissingCamera) {
  Config config;
  config.cameras.source = CameraSource::Libcamera;
  config.cameras.frontal = "no-such-frontal";
  config.cameras.lateral = "no-such-lateral";
  auto source = open_libcamera_pair_source(config);
  ASSERT_FALSE(source);
  EXPECT_NE(source.error().message.find("\"no-such-frontal\": not found"), std::string::npos)
      << source.error().message;
}

#else

TEST(LibcameraCamera, WithoutLibcameraEveryCallSaysSo) {
  EXPECT_FALSE(libcamera_built());
  auto camera = LibcameraCamera::open({.id = "any"});
  ASSERT_FALSE(camera);
  EXPECT_NE(camera.error().message.find("not available in this build"), std::string::npos);
  EXPECT_FALSE(list_libcamera_cameras());
}

#endif

}  // namespace
}  // namespace spinewatch

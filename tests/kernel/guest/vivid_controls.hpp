#pragma once
// vivid's private controls (drivers/media/test-drivers/vivid/vivid-ctrls.c,
// Linux 6.1); the driver exports no header for them.
#include <cstdint>

namespace spinewatch::kernel_test::vivid {

inline constexpr std::uint32_t kVividBase = 0x00f00000 | 0xf000;  // VIDIOC class "Vivid"
inline constexpr std::uint32_t kOsdTextMode = kVividBase + 1;      // 0 all, 1 counters only, 2 none
inline constexpr std::uint32_t kLoopVideo = kVividBase + 37;       // loop the output into the capture
inline constexpr std::uint32_t kDisconnect = kVividBase + 65;      // button: emulate a USB unplug

}  // namespace spinewatch::kernel_test::vivid

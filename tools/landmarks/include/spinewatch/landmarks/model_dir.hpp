#pragma once
// Where scripts/install-deps puts BlazePose's models from the npm package
// @mediapipe/pose (weights are installed from the package, never fetched at
// run time); SPINEWATCH_MEDIAPIPE_DIR overrides it.
#include <cstdlib>
#include <string>

namespace spinewatch::landmarks {

inline std::string mediapipe_dir() {
  const char* dir = std::getenv("SPINEWATCH_MEDIAPIPE_DIR");
  return dir != nullptr && *dir != '\0' ? dir : "/usr/local/share/spinewatch/mediapipe";
}

}  // namespace spinewatch::landmarks

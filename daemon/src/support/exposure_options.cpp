#include "spinewatch/daemon/exposure_options.hpp"

namespace spinewatch {

ExposureOptions exposure_options(const Config& config) {
  ExposureOptions o;
  o.interval_ns = std::int64_t(config.exposure.interval_s) * 1'000'000'000;
  return o;
}

}  // namespace spinewatch

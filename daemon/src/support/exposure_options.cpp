#include "spinewatch/daemon/exposure_options.hpp"

namespace spinewatch {

ExposureOptions exposure_options(const Config& config) {
  ExposureOptions o;
  o.interval_ns = std::int64_t(config.exposure.interval_s) * 1'000'000'000;
  return o;
}

StoreOptions store_options(const Config& config) {
  StoreOptions o;
  o.path = config.storage.path;
  o.retention_days = config.storage.retention_days;
  o.max_size_mb = config.storage.max_size_mb;
  return o;
}

}  // namespace spinewatch

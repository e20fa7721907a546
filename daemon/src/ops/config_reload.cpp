#include "spinewatch/daemon/config_reload.hpp"

#include <functional>
#include <sstream>
#include <type_traits>

namespace spinewatch {
namespace {

struct Field {
  const char* key;
  std::function<std::string(const Config&)> value;  // a printable form, for comparison only
};

template <class T>
std::string text(const T& v) {
  std::ostringstream s;
  if constexpr (std::is_enum_v<T>)
    s << static_cast<int>(v);  // a mode: compared, never shown
  else
    s << v;
  return s.str();
}

#define SW_FIELD(section, name) Field{#section "." #name, [](const Config& c) { return text(c.section.name); }}

const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
      SW_FIELD(station, name),
      SW_FIELD(cameras, source), SW_FIELD(cameras, frontal), SW_FIELD(cameras, lateral),
      SW_FIELD(cameras, pixel_format), SW_FIELD(cameras, width), SW_FIELD(cameras, height),
      SW_FIELD(cameras, fps), SW_FIELD(cameras, exposure_us), SW_FIELD(cameras, gain),
      SW_FIELD(cameras, buffers), SW_FIELD(cameras, calibration), SW_FIELD(cameras, recording), SW_FIELD(cameras, replay),
      SW_FIELD(cameras, watchdog_s),
      SW_FIELD(trigger, mode), SW_FIELD(trigger, chip), SW_FIELD(trigger, line),
      SW_FIELD(trigger, pulse_us), SW_FIELD(trigger, frame_latency_us), SW_FIELD(trigger, controller),
      SW_FIELD(silhouette, background), SW_FIELD(silhouette, learn_frames), SW_FIELD(silhouette, threshold),
      SW_FIELD(silhouette, min_blob_px), SW_FIELD(silhouette, chroma_threshold),
      SW_FIELD(silhouette, shadow_ratio), SW_FIELD(silhouette, background_frontal),
      SW_FIELD(silhouette, background_lateral), SW_FIELD(silhouette, adapt_s), SW_FIELD(silhouette, adapt_margin_px),
      SW_FIELD(silhouette, relearn_empty_s), SW_FIELD(silhouette, bootstrap),
      SW_FIELD(cvsm, model), SW_FIELD(cvsm, subject_frames), SW_FIELD(cvsm, lost_cost), SW_FIELD(cvsm, refine_steps), SW_FIELD(cvsm, limbs),
      SW_FIELD(spine, model), SW_FIELD(spine, voxel_mm), SW_FIELD(spine, substeps),
      SW_FIELD(subject, stature_mm), SW_FIELD(subject, mass_kg), SW_FIELD(subject, c7_height_mm),
      SW_FIELD(subject, iliac_crest_height_mm), SW_FIELD(subject, height_mm), SW_FIELD(subject, spine_placement),
      SW_FIELD(publish, listen), SW_FIELD(publish, allow_unauthenticated), SW_FIELD(publish, unix_socket), SW_FIELD(publish, unix_socket_group),
      SW_FIELD(publish, client_queue),
      SW_FIELD(publish, max_clients), SW_FIELD(publish, tls_cert), SW_FIELD(publish, tls_key),
      SW_FIELD(publish, tls_client_ca), SW_FIELD(publish, token_file), SW_FIELD(publish, auth_timeout_s),
      SW_FIELD(exposure, interval_s),
      SW_FIELD(alerts, enabled), SW_FIELD(alerts, rules), SW_FIELD(alerts, silent), SW_FIELD(alerts, gpio_chip),
      SW_FIELD(alerts, gpio_line), SW_FIELD(alerts, gpio_active_low), SW_FIELD(alerts, gpio_mode),
      SW_FIELD(alerts, pulse_ms),
      SW_FIELD(storage, path), SW_FIELD(storage, posture_every), SW_FIELD(storage, retention_days),
      SW_FIELD(storage, max_size_mb),
      SW_FIELD(http, listen), SW_FIELD(http, allow_unauthenticated), SW_FIELD(http, fps), SW_FIELD(http, camera_pixels),
      SW_FIELD(http, max_connections), SW_FIELD(http, timeout_s), SW_FIELD(http, tls_cert), SW_FIELD(http, tls_key),
      SW_FIELD(http, tls_client_ca), SW_FIELD(http, token_file),
      SW_FIELD(log, level), SW_FIELD(log, status_interval_s),
      SW_FIELD(mqtt, url), SW_FIELD(mqtt, ca_file), SW_FIELD(mqtt, cert_file), SW_FIELD(mqtt, key_file),
      SW_FIELD(mqtt, username), SW_FIELD(mqtt, password_file), SW_FIELD(mqtt, posture_rate_hz), SW_FIELD(mqtt, qos),
      SW_FIELD(mqtt, outbox_path), SW_FIELD(mqtt, outbox_max_messages), SW_FIELD(mqtt, keepalive_s),
      SW_FIELD(mqtt, reconnect_min_s), SW_FIELD(mqtt, reconnect_max_s),
      SW_FIELD(privacy, pseudonymise), SW_FIELD(privacy, secret_file),
  };
  return table;
}

#undef SW_FIELD

}  // namespace

std::vector<std::string> changed_keys(const Config& before, const Config& after) {
  std::vector<std::string> changed;
  for (const auto& f : fields())
    if (f.value(before) != f.value(after)) changed.emplace_back(f.key);
  return changed;
}

bool reloadable_key(const std::string& key) {
  return key == "station.name" || key == "log.level" || key == "log.status_interval_s" || key == "subject.stature_mm" ||
         key == "subject.mass_kg" || key == "subject.c7_height_mm" || key == "subject.iliac_crest_height_mm" ||
         key == "alerts.silent";
}

std::vector<std::string> compared_keys() {
  std::vector<std::string> keys;
  for (const auto& f : fields()) keys.emplace_back(f.key);
  return keys;
}

}  // namespace spinewatch

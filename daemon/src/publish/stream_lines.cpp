#include "publish/stream_lines.hpp"

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/version.hpp"

namespace spinewatch {
namespace {

nlohmann::json matrix_rows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(std::move(row));
  }
  return rows;
}

// The same nodes as calibration.yaml, so a client can project the posture.
nlohmann::json camera_json(const CameraModel& camera) {
  return {{"camera_matrix", matrix_rows(camera.camera_matrix)},
          {"dist_coeffs", camera.distortion()},
          {"R", matrix_rows(camera.R)},
          {"t", {camera.t.x(), camera.t.y(), camera.t.z()}}};
}

}  // namespace

std::string make_hello_line(const std::string& station, const CameraRig& rig, const std::string& source,
                            const std::vector<std::string>& warnings) {
  nlohmann::json hello = {{"class", "hello"},
                          {"v", kPostureSchemaVersion},
                          {"daemon_version", kVersion},
                          {"station", station},
                          {"rig", {{"frontal", camera_json(rig.frontal)}, {"lateral", camera_json(rig.lateral)}}},
                          {"source", source}};
  if (!warnings.empty()) hello["warnings"] = warnings;
  return hello.dump();
}

std::string encode_posture_line(const Posture& posture, const StreamStats& stats) {
  auto line = to_json(posture);
  line["stats"] = {{"pairs", stats.pairs},
                   {"pairs_dropped", stats.pairs_dropped},
                   {"frames_lost", stats.frames_lost},
                   {"clients", stats.clients},
                   {"clients_dropped", stats.clients_dropped},
                   {"background_updates", posture.background.updates},
                   {"background_relearns", posture.background.relearns},
                   {"background_bootstraps", posture.background.bootstraps}};
  if (stats.mqtt) {
    auto& s = line["stats"];
    s["mqtt_connected"] = stats.mqtt_connected;
    s["mqtt_outbox"] = stats.mqtt_outbox;
    s["mqtt_dropped"] = stats.mqtt_dropped;
    s["mqtt_reconnects"] = stats.mqtt_reconnects;
  }
  return line.dump();
}

}  // namespace spinewatch

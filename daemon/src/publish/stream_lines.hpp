#pragma once
// The daemon's lines on top of the posture stream (docs/protocol.md): the
// hello line each client gets first, and posture lines carrying the
// daemon's counters as the optional "stats" object.
#include <cstdint>
#include <string>
#include <vector>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

struct StreamStats {
  std::uint64_t pairs = 0;            // pairs taken from the source since start
  std::uint64_t pairs_dropped = 0;    // pairs the estimator had no time for
  std::uint64_t frames_lost = 0;      // frames that never became part of a pair
  std::uint64_t clients = 0;          // clients connected now
  std::uint64_t clients_dropped = 0;  // clients dropped since start
  // With [mqtt] url set (docs/fleet.md): the link (1 up, 0 down), the
  // outbox's messages, MQTT messages dropped (all reasons), reconnections.
  bool mqtt = false;
  std::uint64_t mqtt_connected = 0, mqtt_outbox = 0, mqtt_dropped = 0, mqtt_reconnects = 0;
};

// {"class":"hello","v":1,"daemon_version":…,"station":…,"rig":{…},"source":…}
// `warnings`: what every client should know about this station's setup
// (an unauthenticated network listener); the field is absent when none.
std::string make_hello_line(const std::string& station, const CameraRig& rig, const std::string& source,
                            const std::vector<std::string>& warnings = {});
// encode_posture(posture) plus "stats":{…}.
std::string encode_posture_line(const Posture& posture, const StreamStats& stats);

}  // namespace spinewatch

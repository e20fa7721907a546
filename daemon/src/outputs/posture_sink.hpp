#pragma once
// The daemon's output seam: everything a posture, a summary or an alert
// goes to (the stream's publisher, the station's store, MQTT, the alert
// line, the live view) is a PostureSink. The daemon holds its sinks in one
// list, in the order they stop; it hands each event to every sink in turn
// and walks the same list for /state, /metrics and the status line. A new
// output is one class implementing this, added where the sinks are listed
// (daemon/src/app/outputs.cpp) or, from a test, through DaemonParts.
#include <string>
#include <string_view>

#include "exposure/summary_stream.hpp"
#include "http/daemon_metrics.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/frames/frame_pair.hpp"
#include "support/note_level.hpp"

namespace spinewatch {

// One posture as the estimator thread hands it out. Valid during the call only.
struct PostureEvent {
  const Posture& posture;
  const FramePair& pair;        // the pair it came from; a camera_lost marker has no frames
  const EstimatorTrace& trace;  // what the estimator saw for it (all null for a marker)
  const std::string& line;      // the stream's posture line, without its newline
};

class PostureSink {
 public:
  virtual ~PostureSink() = default;
  // For the log.
  virtual std::string_view name() const = 0;

  // Estimator thread; must not block (hand over to a queue or drop).
  virtual void on_posture(const PostureEvent& event) = 0;
  // An exposure summary closed; `worker` is the id it is labelled with ("" when none).
  virtual void on_summary(const SummaryLine& /*summary*/, const std::string& /*worker*/) {}
  // An alert raised or cleared; `line` is its stream line.
  virtual void on_alert(const AlertEvent& /*event*/, const std::string& /*line*/) {}
  // The station's own notes (start, reload, stop), for outputs that keep a
  // log; any thread.
  virtual void on_note(NoteLevel /*level*/, std::string_view /*message*/) {}

  // Its counters: into the metrics (/metrics, /state, the posture lines'
  // stats) and, as "; …", onto the status line (sd_notify, the log).
  virtual void add_metrics(DaemonMetrics& /*metrics*/) const {}
  virtual void add_status(std::string& /*text*/) const {}

  // Called once, after the pipeline has stopped, in list order.
  virtual void stop() = 0;
};

}  // namespace spinewatch

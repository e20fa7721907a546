#include <fmt/format.h>

#include "outputs/sinks.hpp"

namespace spinewatch {

void StoreSink::on_posture(const PostureEvent& event) {
  if (event.posture.seq % posture_every_ == 0) store_->add_posture(event.posture.seq, event.posture.t_ns, event.line);
}

void StoreSink::on_summary(const SummaryLine& s, const std::string& worker) {
  store_->add_summary(s.summary.scope, s.summary.start_ns, s.summary.end_ns, worker, s.line);
}

void StoreSink::on_alert(const AlertEvent& event, const std::string& line) { store_->add_alert(event.t_ns, line); }

void StoreSink::on_note(NoteLevel level, std::string_view message) {
  store_->add_event(level, std::string(message));
}

void StoreSink::add_status(std::string& text) const {
  const StoreStats st = store_->stats();
  text += fmt::format("; storage {} written, {} dropped, {} failed", st.written, st.dropped, st.failed);
}

}  // namespace spinewatch

#include <fmt/format.h>

#include "outputs/sinks.hpp"

namespace spinewatch {

void MqttSink::add_status(std::string& text) const {
  const MqttStats q = mqtt_->stats();
  text += fmt::format("; mqtt {}, outbox {}, {} dropped, {} reconnects", q.connected ? "up" : "down",
                      q.outbox_messages, q.dropped(), q.reconnects);
}

}  // namespace spinewatch

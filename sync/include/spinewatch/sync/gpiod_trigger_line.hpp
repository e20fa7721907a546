#pragma once
// The trigger line on a GPIO chip through libgpiod 1.6's C++ binding.
#include <memory>
#include <string>

#include "spinewatch/frames/result.hpp"
#include "spinewatch/sync/trigger_line.hpp"

namespace spinewatch::sync {

// `chip` is a name ("gpiochip0"), a path ("/dev/gpiochip0") or a label.
// The line is requested as an output driven inactive (low), and driven
// inactive again when released. active_low: set(true) drives the pin low
// (a lamp or buzzer wired to the supply), so inactive is high.
Result<std::unique_ptr<TriggerOutputLine>> open_gpiod_output(const std::string& chip, unsigned line,
                                                             const std::string& consumer = "spinewatch",
                                                             bool active_low = false);
// The line is requested for rising-edge events. Event timestamps are on
// CLOCK_MONOTONIC from Linux 5.7, CLOCK_REALTIME before: the first event
// tells which, and realtime stamps are converted to monotonic.
Result<std::unique_ptr<TriggerInputLine>> open_gpiod_input(const std::string& chip, unsigned line,
                                                           const std::string& consumer = "spinewatch");

}  // namespace spinewatch::sync

#include <fmt/format.h>

#include "outputs/sinks.hpp"

namespace spinewatch {

void AlertLineSink::add_status(std::string& text) const {
  if (!output_) {
    text += "; alert line not open: alerts not signalled";
    return;
  }
  const AlertOutputStats a = output_->stats();
  text += fmt::format("; alert line {}{}, {} signalled, {} write errors", output_->name(),
                      output_->silent() ? " (silent)" : a.signalling ? " signalling" : "", a.signalled, a.write_errors);
}

}  // namespace spinewatch

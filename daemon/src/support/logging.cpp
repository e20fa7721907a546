#include "spinewatch/daemon/logging.hpp"

#include <cstdlib>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace spinewatch {

bool running_under_journal() {
  const char* stream = std::getenv("JOURNAL_STREAM");
  return stream != nullptr && *stream != '\0';
}

void setup_logging(std::string_view level) {
  spdlog::drop("spinewatch");  // idempotent: tests and SIGHUP may call it again
  auto logger = spdlog::stderr_color_mt("spinewatch");
  logger->set_pattern(running_under_journal() ? "%l: %v" : "%Y-%m-%d %H:%M:%S.%e %^%l%$: %v");
  logger->set_level(spdlog::level::from_str(std::string(level)));
  spdlog::set_default_logger(std::move(logger));
}

}  // namespace spinewatch

#include "spinewatch/sync/trigger_source.hpp"

#include <fmt/format.h>

#include "spinewatch/sync/gpiod_trigger_line.hpp"

namespace spinewatch::sync {

std::string_view to_string(TriggerMode mode) {
  switch (mode) {
    case TriggerMode::FreeRun: return "free-run";
    case TriggerMode::Master: return "master";
    case TriggerMode::Slave: return "slave";
  }
  return "?";
}

Result<std::unique_ptr<TriggerSource>> TriggerSource::open(const TriggerSourceOptions& options, EdgeCallback on_edge) {
  switch (options.mode) {
    case TriggerMode::FreeRun:
      return std::unique_ptr<TriggerSource>{};
    case TriggerMode::Master: {
      auto line = open_gpiod_output(options.chip, options.line, options.consumer);
      if (!line) return line.error();
      return master(std::move(line).value(), TriggerMasterOptions{.fps = options.fps, .pulse_us = options.pulse_us},
                    std::move(on_edge));
    }
    case TriggerMode::Slave: {
      auto line = open_gpiod_input(options.chip, options.line, options.consumer);
      if (!line) return line.error();
      return slave(std::move(line).value(), std::move(on_edge));
    }
  }
  return Error{fmt::format("trigger mode {}: not a mode", static_cast<int>(options.mode))};
}

std::unique_ptr<TriggerSource> TriggerSource::master(std::unique_ptr<TriggerOutputLine> line,
                                                     TriggerMasterOptions options, EdgeCallback on_edge) {
  std::unique_ptr<TriggerSource> source(new TriggerSource);
  source->output_ = std::move(line);
  source->master_ = std::make_unique<TriggerMaster>(*source->output_, options, std::move(on_edge));
  return source;
}

std::unique_ptr<TriggerSource> TriggerSource::slave(std::unique_ptr<TriggerInputLine> line, EdgeCallback on_edge) {
  std::unique_ptr<TriggerSource> source(new TriggerSource);
  source->input_ = std::move(line);
  source->slave_ = std::make_unique<TriggerSlave>(*source->input_, std::move(on_edge));
  return source;
}

TriggerSource::~TriggerSource() { stop(); }

void TriggerSource::stop() {
  if (master_) master_->stop();
  if (slave_) slave_->stop();
}

std::uint64_t TriggerSource::edges() const {
  if (master_) return master_->edges();
  if (slave_) return slave_->edges();
  return 0;
}

}  // namespace spinewatch::sync

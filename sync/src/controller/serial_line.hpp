#pragma once
// A serial port spoken to in lines, each read or write bounded by a
// deadline (Boost.Asio serial_port driven by its own io_context).
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::sync {

class SerialLine {
 public:
  // 8N1, no flow control, raw mode.
  static Result<std::unique_ptr<SerialLine>> open(const std::string& device, unsigned baud);
  ~SerialLine();
  SerialLine(const SerialLine&) = delete;
  SerialLine& operator=(const SerialLine&) = delete;

  Status write_line(std::string_view line, std::chrono::milliseconds timeout);  // appends "\n"
  // The next line without its "\n" (and "\r"); nothing when none arrived in time.
  Result<std::optional<std::string>> read_line(std::chrono::milliseconds timeout);
  void discard_input();  // stale bytes from before a request

 private:
  struct Impl;
  explicit SerialLine(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch::sync

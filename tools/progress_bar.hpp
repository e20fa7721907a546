#pragma once
// A one-line progress bar on standard error, drawn only when standard error
// is a terminal (docs/interfaces.md §4: nothing extra when it is not).
#include <cstdint>
#include <string>

namespace spinewatch::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();  // ends the line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::uint64_t done, std::uint64_t total);

 private:
  std::string label_;
  bool enabled_;
  int last_permille_ = -1;
  bool drawn_ = false;
};

}  // namespace spinewatch::cli

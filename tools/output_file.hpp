#pragma once
// An output stream for FILE or "-" (standard output). A file is written to
// FILE.part and renamed on commit(), so an interrupted run leaves no
// half-written FILE.
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::cli {

class OutputFile {
 public:
  static Result<std::unique_ptr<OutputFile>> open(const std::string& target);
  ~OutputFile();  // removes FILE.part when not committed

  std::ostream& stream() { return *out_; }
  Status commit();

 private:
  OutputFile() = default;
  std::filesystem::path final_, part_;
  std::unique_ptr<std::ofstream> file_;
  std::ostream* out_ = nullptr;
  bool committed_ = false;
};

// The whole of `text` into FILE (or standard output for "-"), all or nothing.
Status write_output(const std::string& target, std::string_view text);

}  // namespace spinewatch::cli

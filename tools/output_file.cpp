#include "output_file.hpp"

#include <iostream>

#include <fmt/format.h>

namespace spinewatch::cli {

Result<std::unique_ptr<OutputFile>> OutputFile::open(const std::string& target) {
  std::unique_ptr<OutputFile> out(new OutputFile());
  if (target == "-") {
    out->out_ = &std::cout;
    out->committed_ = true;
    return out;
  }
  out->final_ = target;
  out->part_ = target + ".part";
  out->file_ = std::make_unique<std::ofstream>(out->part_, std::ios::binary | std::ios::trunc);
  if (!*out->file_) return Error{fmt::format("{}: cannot be written", target)};
  out->out_ = out->file_.get();
  return out;
}

OutputFile::~OutputFile() {
  if (!committed_ && file_) {
    file_->close();
    std::error_code ec;
    std::filesystem::remove(part_, ec);
  }
}

Status OutputFile::commit() {
  out_->flush();
  if (!*out_) return Error{fmt::format("{}: write failed", final_.empty() ? "standard output" : final_.string())};
  if (file_) {
    file_->close();
    std::error_code ec;
    std::filesystem::rename(part_, final_, ec);
    if (ec) return Error{fmt::format("{}: {}", final_.string(), ec.message())};
  }
  committed_ = true;
  return Ok{};
}

Status write_output(const std::string& target, std::string_view text) {
  auto out = OutputFile::open(target);
  if (!out) return out.error();
  (*out)->stream() << text;
  return (*out)->commit();
}

}  // namespace spinewatch::cli

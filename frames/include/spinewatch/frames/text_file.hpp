#pragma once
// A whole input file's text, read one way with one wording of failure, for
// every parser of a file (configuration, models, subjects, recordings,
// targets, ANSUR tables): "<path>: cannot open: <reason>" (the system's
// reason: "No such file or directory", "Is a directory", "Permission
// denied"), or "<path>: larger than N bytes" — no input file of ours comes
// near the cap (256 MiB), which keeps /dev/zero or a runaway file out of memory.
#include <cstddef>
#include <filesystem>
#include <string>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

inline constexpr std::size_t kMaxTextFileBytes = std::size_t{256} << 20;

Result<std::string> read_text_file(const std::filesystem::path& path, std::size_t max_bytes = kMaxTextFileBytes);

}  // namespace spinewatch

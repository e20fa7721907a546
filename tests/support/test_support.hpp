#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture.hpp"

namespace spinewatch::test {

// This build's source and build trees and its two programs (generated:
// tests/CMakeLists.txt).
const std::string& source_dir();
const std::string& binary_dir();
const std::string& cli_path();     // spinewatch
const std::string& daemon_path();  // spinewatchd

// How much longer a wait on the estimator may take in this build. Under
// ASan and UBSan every memory access of the CVSM's bit loops is checked:
// building a subject model (≈ 2 000 cost evaluations over the first ten
// pairs) takes 5–7 s instead of 0.4 s, and a test waiting 2 s for the
// first postures, or for a daemon to stop while it is in that work,
// would fail on the build, not on the behaviour.
inline constexpr int kTimeScale = SPINEWATCH_TEST_TIME_SCALE;
template <class Duration>
constexpr Duration scaled(Duration d) {
  return d * kTimeScale;
}

// Under the sanitizers a sweep that runs the same code over like cases
// (subjects, scenarios) runs a sample of them: ASan and UBSan check the
// code, which every case runs, and a case costs 5-7x its release time
// there. The release build runs every case and asserts each one's figures
// (docs/testing.md, "How the sanitizer stage is kept...").
inline constexpr bool kSanitized = SPINEWATCH_TEST_SANITIZED;

// The cases this build runs: all of them, or under the sanitizers every
// `stride`-th from the first (the first always: a sweep never runs empty;
// a stride of 0 keeps every case).
template <class Case>
std::vector<Case> sanitizer_sample(const std::vector<Case>& cases, std::size_t stride) {
  if (!kSanitized || stride <= 1) return cases;
  std::vector<Case> kept;
  for (std::size_t i = 0; i < cases.size(); i += stride) kept.push_back(cases[i]);
  return kept;
}

// A plausible tracking posture: seq 17, t_ns 566666666, a gently curved
// spine rotating a little per level, fit cost 0.031, latency 412 µs.
Posture sample_tracking_posture();

// A fresh directory under the build tree, removed when the object goes.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

void write_file(const std::filesystem::path& path, const std::string& text);
std::string read_file(const std::filesystem::path& path);
// Every line of an NDJSON file, parsed (a line that is not JSON throws).
std::vector<nlohmann::json> read_ndjson(const std::filesystem::path& path);
std::filesystem::path source_path(const std::string& relative);  // in the source tree

// A TCP port on 127.0.0.1 that was free a moment ago (the kernel's pick),
// for a server the test starts next.
std::uint16_t free_port();

struct CommandResult {
  int exit_code = -1;
  std::string output;  // standard output and standard error together
};
// Runs a shell command line and captures what it prints.
CommandResult run_command(const std::string& command_line);
// Runs the spinewatch CLI with the given arguments (already shell-quoted).
CommandResult run_cli(const std::string& args);

// Validates every line of an NDJSON file against docs/posture.schema.json
// (hello lines against the hello schema), with Debian's python3-jsonschema.
// Returns "" when valid, else the validator's message.
std::string validate_ndjson(const std::filesystem::path& file);

}  // namespace spinewatch::test

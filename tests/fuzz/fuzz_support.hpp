#pragma once
// What the harnesses share: a scratch directory of the process's own for
// the parsers whose public entry reads a file, and a check that stops the
// run (libFuzzer then saves the input) when a property of the parser's
// answer does not hold. The property checks are what makes a harness more
// than a crash detector: one clear message for bad input, and a good
// answer that is internally consistent.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace spinewatch::fuzz {

// Created on first use (on /dev/shm when there is one: the harnesses write
// a file per input), removed at exit.
const std::filesystem::path& scratch_dir();

// Writes the input as `path` (replacing it) and returns `path`.
const std::filesystem::path& write_input(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size);

std::string_view as_text(const std::uint8_t* data, std::size_t size);

// Prints "property failed: <what>: <detail>" and aborts.
[[noreturn]] void fail(std::string_view what, std::string_view detail);

// The rule every parser's error follows (docs/testing.md, "Fuzzing"):
// a non-empty message, one line, naming the source it was given
// (`source` empty: no name to check).
void check_one_clear_message(const std::string& message, std::string_view source);

// Quiets spdlog (warnings about truncated frames and the like would flood
// the fuzzer's output).
void silence_logging();

}  // namespace spinewatch::fuzz

#define FUZZ_CHECK(cond, detail)                                       \
  do {                                                                 \
    if (!(cond)) ::spinewatch::fuzz::fail(#cond, (detail));            \
  } while (0)

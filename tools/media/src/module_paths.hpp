#pragma once
// Where the media module is, written by CMake into one generated file
// (module_paths.cpp in the build tree) so that no other source's command
// line carries the build's paths.
#include <filesystem>

namespace spinewatch::media::detail {
const std::filesystem::path& build_dir();                  // this build tree
const std::filesystem::path& built_module();               // the module in it
const std::filesystem::path& installed_module_from_bindir();  // relative to the installed programs' directory
}  // namespace spinewatch::media::detail

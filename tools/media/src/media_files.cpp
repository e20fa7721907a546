#include "spinewatch/media/media_files.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <system_error>

#include <fmt/format.h>

#include "module_abi.hpp"
#include "module_paths.hpp"

namespace spinewatch::media {
namespace {

bool inside(const std::filesystem::path& file, const std::filesystem::path& dir) {
  const auto [d, f] = std::mismatch(dir.begin(), dir.end(), file.begin(), file.end());
  return d == dir.end();
}

// The module stays loaded for the life of the process: readers it made
// and OpenCV's codec state may outlive any one caller, and unloading it at
// exit would only cost the leak checker its symbols.
Result<const ModuleFunctions*> load(const std::filesystem::path& path) {
  const auto fail = [&](std::string why) {
    // dlerror() starts with the file's name; the message names it once.
    if (const std::string prefix = path.string() + ": "; why.starts_with(prefix)) why.erase(0, prefix.size());
    return Error{fmt::format("{}: the media module (video and image files) could not be loaded ({}). It is part of "
                             "the spinewatch package (reinstall it) or, in a build tree, of the build "
                             "(cmake --build the preset again)",
                             path.string(), why)};
  };
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    return fail(why ? why : "dlopen gave no reason");
  }
  void* entry = dlsym(handle, kModuleEntry);
  if (!entry) return fail(fmt::format("it has no {}", kModuleEntry));
  const auto* functions = reinterpret_cast<const ModuleFunctions* (*)()>(entry)();
  if (!functions || functions->size != sizeof(ModuleFunctions))
    return fail("it is from another build of spinewatch");
  return functions;
}

const Result<const ModuleFunctions*>& module() {
  static const Result<const ModuleFunctions*> loaded = load(module_path());
  return loaded;
}

}  // namespace

std::filesystem::path module_path() {
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path build = std::filesystem::weakly_canonical(detail::build_dir(), ec);
  if (!program.empty() && !build.empty() && inside(program, build)) return detail::built_module();
  return (program.parent_path() / detail::installed_module_from_bindir()).lexically_normal();
}

Result<std::unique_ptr<VideoReader>> open_video(const std::filesystem::path& path) {
  const auto& m = module();
  if (!m) return m.error();
  return (*m)->open_video(path.string());
}

Result<cv::Mat> read_image(const std::filesystem::path& path, int flags) {
  const auto& m = module();
  if (!m) return m.error();
  return (*m)->read_image(path.string(), flags);
}

Result<bool> write_image(const std::filesystem::path& path, const cv::Mat& image, const std::vector<int>& params) {
  const auto& m = module();
  if (!m) return m.error();
  return (*m)->write_image(path.string(), image, params);
}

}  // namespace spinewatch::media

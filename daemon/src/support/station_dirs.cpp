#include "support/station_dirs.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

namespace spinewatch {
namespace {

std::string env_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr ? std::string(value) : std::string();
}

std::string first_entry(const std::string& list) { return list.substr(0, list.find(':')); }

}  // namespace

DirEnvironment DirEnvironment::of_process() {
  DirEnvironment env;
  env.runtime_directory = env_or_empty("RUNTIME_DIRECTORY");
  env.state_directory = env_or_empty("STATE_DIRECTORY");
  env.xdg_runtime_dir = env_or_empty("XDG_RUNTIME_DIR");
  env.xdg_state_home = env_or_empty("XDG_STATE_HOME");
  env.home = env_or_empty("HOME");
  env.uid = static_cast<unsigned>(::getuid());
  env.writable_dir = [](const std::filesystem::path& dir) {
    std::error_code ec;
    return std::filesystem::is_directory(dir, ec) && ::access(dir.c_str(), W_OK | X_OK) == 0;
  };
  return env;
}

std::filesystem::path runtime_dir(const DirEnvironment& env) {
  if (!env.runtime_directory.empty()) return first_entry(env.runtime_directory);
  if (env.writable_dir && env.writable_dir(kSystemRuntimeDir)) return kSystemRuntimeDir;
  if (!env.xdg_runtime_dir.empty()) return std::filesystem::path(env.xdg_runtime_dir) / "spinewatch";
  return fmt::format("/tmp/spinewatch-{}", env.uid);
}

std::filesystem::path state_dir(const DirEnvironment& env) {
  if (!env.state_directory.empty()) return first_entry(env.state_directory);
  if (env.writable_dir && env.writable_dir(kSystemStateDir)) return kSystemStateDir;
  if (!env.xdg_state_home.empty()) return std::filesystem::path(env.xdg_state_home) / "spinewatch";
  return std::filesystem::path(env.home.empty() ? "/" : env.home) / ".local/state/spinewatch";
}

Result<std::filesystem::path> default_station_file(StationDir dir, std::string_view file, std::string_view key,
                                                   const DirEnvironment& env) {
  const bool runtime = dir == StationDir::Runtime;
  const std::filesystem::path chosen = runtime ? runtime_dir(env) : state_dir(env);
  const bool systemd = !(runtime ? env.runtime_directory : env.state_directory).empty();
  if (!systemd && chosen != (runtime ? kSystemRuntimeDir : kSystemStateDir))
    if (auto s = ensure_private_dir(chosen, key); !s) return s.error();
  return chosen / file;
}

Status ensure_private_dir(const std::filesystem::path& dir, std::string_view key) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    if (!dir.parent_path().empty()) std::filesystem::create_directories(dir.parent_path(), ec);
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
      return Error{fmt::format("{}: cannot make the directory {}: {} (set {} to a path you may write)", key,
                               dir.string(), std::strerror(errno), key)};
  }
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0)
    return Error{fmt::format("{}: {}: {} (set {} to a path you may write)", key, dir.string(), std::strerror(errno), key)};
  if (!S_ISDIR(st.st_mode))
    return Error{fmt::format("{}: {} is not a directory (set {} to another path)", key, dir.string(), key)};
  if (st.st_uid != ::getuid() || (st.st_mode & 0022) != 0)
    return Error{fmt::format("{}: {} belongs to another user or others may write to it; remove it, or set {} to "
                             "another path", key, dir.string(), key)};
  return Ok{};
}

}  // namespace spinewatch

#pragma once
// Where the daemon keeps its runtime files (the Unix socket) and its state
// (the MQTT outbox, the pseudonym secret) when the configuration leaves the
// path empty (docs/daemon.md, "Files a daemon started by hand uses").
//
// Under systemd, RuntimeDirectory= and StateDirectory= set
// $RUNTIME_DIRECTORY and $STATE_DIRECTORY: those win. Otherwise the
// system directories /run/spinewatch and /var/lib/spinewatch are used when
// they exist and this process may write there (a packaged station); a
// daemon started by hand by anyone else uses the XDG base directories of
// its user, so that the annotated config works as it is, off systemd.
#include <filesystem>
#include <functional>
#include <string>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// The environment the choice reads, apart so that tests can give one.
struct DirEnvironment {
  std::string runtime_directory;  // $RUNTIME_DIRECTORY (systemd), colon-separated
  std::string state_directory;    // $STATE_DIRECTORY (systemd), colon-separated
  std::string xdg_runtime_dir;    // $XDG_RUNTIME_DIR
  std::string xdg_state_home;     // $XDG_STATE_HOME
  std::string home;               // $HOME
  unsigned uid = 0;
  // Whether a system directory exists and may be written by this process.
  std::function<bool(const std::filesystem::path&)> writable_dir;

  static DirEnvironment of_process();
};

inline const std::filesystem::path kSystemRuntimeDir = "/run/spinewatch";
inline const std::filesystem::path kSystemStateDir = "/var/lib/spinewatch";

// $RUNTIME_DIRECTORY's first entry; else /run/spinewatch when writable;
// else $XDG_RUNTIME_DIR/spinewatch; else /tmp/spinewatch-UID.
std::filesystem::path runtime_dir(const DirEnvironment& env);
// $STATE_DIRECTORY's first entry; else /var/lib/spinewatch when writable;
// else $XDG_STATE_HOME/spinewatch; else $HOME/.local/state/spinewatch.
std::filesystem::path state_dir(const DirEnvironment& env);

enum class StationDir { Runtime, State };

// `file` in that directory (runtime_dir or state_dir of `env`). A user's own
// fallback directory is made (ensure_private_dir); a systemd or system
// directory is used as it is. Errors name `key`.
Result<std::filesystem::path> default_station_file(StationDir dir, std::string_view file, std::string_view key,
                                                   const DirEnvironment& env = DirEnvironment::of_process());

// Makes `dir` (and its parents) when missing, the last one private to this
// user (0700); refuses a directory another user owns or others may write to,
// as /tmp/spinewatch-UID could be made by anyone first. Errors name `key`
// (the configuration key whose default it is) and how to choose another path.
Status ensure_private_dir(const std::filesystem::path& dir, std::string_view key);

}  // namespace spinewatch

#pragma once
// Worker ids under a pseudonym (docs/security.md, "Pseudonyms"): what the
// station stores, publishes and logs in place of the id a client gave is
// "w-" and the first 12 hex digits of HMAC-SHA256(station secret, id).
// The same id gives the same pseudonym on this station across restarts
// (the secret is kept in a file), another station's differ, and without
// the secret a pseudonym cannot be tied to an id by trying likely ids.
#include <filesystem>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

class Pseudonyms {
 public:
  // Reads the secret (64 hex digits), creating the file with a fresh random
  // one, mode 0600, when it does not exist. A file others can read, or
  // holding anything else, is refused; messages name `key` and the path.
  static Result<Pseudonyms> open(const std::filesystem::path& secret_file, std::string_view key = "privacy.secret_file");
  std::string of(std::string_view id) const;

 private:
  explicit Pseudonyms(std::string secret) : secret_(std::move(secret)) {}
  std::string secret_;  // the file's 64 hex digits, used as the HMAC key as they are
};

// pseudonym.key in the state directory: $STATE_DIRECTORY (systemd), else
// /var/lib/spinewatch when writable, else the user's (station_dirs.hpp).
Result<std::filesystem::path> default_secret_path();

}  // namespace spinewatch

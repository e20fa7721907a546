#pragma once
// Who may use a network listener (docs/security.md): TLS with the
// station's certificate, client certificates signed by a configured CA,
// bearer tokens from a file. Loaded once at start from a listener's keys
// ([publish] or [http]); key and token files readable by anyone but their
// owner are refused, since the unit's other defences do not cover a
// secret another local user can read.
#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/frames/result.hpp"

namespace boost::asio::ssl {
class context;
}

namespace spinewatch {

// A listener's access keys as configured ("" = not set).
struct AccessFiles {
  std::string tls_cert{};       // PEM: the station's certificate (chain)
  std::string tls_key{};        // PEM: its private key, mode 0600 or stricter
  std::string tls_client_ca{};  // PEM: clients must present a certificate this CA signed
  std::string token_file{};     // bearer tokens, one a line, "token" or "name:token"; mode 0600 or stricter
};

// Bearer tokens. Only SHA-256 digests are kept; a presented token is
// compared with every one of them in constant time, so neither a match's
// position nor a common prefix shows in the timing.
class TokenSet {
 public:
  // `key` names the setting in messages, e.g. "publish.token_file".
  static Result<TokenSet> load(const std::filesystem::path& path, std::string_view key);
  static TokenSet from_lines(std::string_view text);  // tests; no checks of the file
  // The matching token's name ("name:token"), or "token N" (its line), or nothing.
  std::optional<std::string> match(std::string_view token) const;
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::string name;
    std::array<unsigned char, 32> digest;
  };
  std::vector<Entry> entries_;
};

struct Access {
  std::shared_ptr<boost::asio::ssl::context> tls{};  // null: plain TCP
  std::shared_ptr<const TokenSet> tokens{};          // null: no token asked for
  bool client_certificates = false;                // the TLS handshake requires one
  // Someone is asked who they are (a certificate or a token), not just
  // offered encryption.
  bool authenticates() const { return client_certificates || tokens != nullptr; }
  // What a network bind needs without allow_unauthenticated: TLS and an
  // authentication, so that neither tokens nor postures cross it in clear.
  bool safe_for_network() const { return tls != nullptr && authenticates(); }
  std::string describe() const;  // e.g. "TLS, client certificates, 2 tokens"
};

// `section` is "publish" or "http": messages name "<section>.<key>".
// Errors: a key file or token file with group/other permission bits, a
// certificate without its key (or the reverse), a client CA without TLS,
// an unreadable or empty token file, a certificate OpenSSL refuses.
Result<Access> load_access(const AccessFiles& files, std::string_view section);

// The file's permission bits must leave out group and others (0600, 0400).
Status check_private_file(const std::filesystem::path& path, std::string_view key);

// The token in a TCP client's first line, {"command":"auth","token":"..."};
// nothing when the line is not that command.
std::optional<std::string> auth_token_of(std::string_view line);

// At most one log line per `every` for a repeated refusal; the ones held
// back are counted into the next.
class LogLimiter {
 public:
  explicit LogLimiter(std::chrono::steady_clock::duration every = std::chrono::seconds(10)) : every_(every) {}
  // Whether to log now, and how many were held back since the last one.
  std::optional<std::uint64_t> admit(std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now());

 private:
  std::chrono::steady_clock::duration every_;
  std::optional<std::chrono::steady_clock::time_point> last_;
  std::uint64_t held_ = 0;
};

}  // namespace spinewatch

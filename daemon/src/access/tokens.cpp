#include <openssl/crypto.h>
#include <openssl/evp.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "access/access.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {
namespace {

std::array<unsigned char, 32> sha256(std::string_view text) {
  std::array<unsigned char, 32> out{};
  unsigned int size = 0;
  EVP_Digest(text.data(), text.size(), out.data(), &size, EVP_sha256(), nullptr);
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace

TokenSet TokenSet::from_lines(std::string_view text) {
  TokenSet set;
  std::size_t number = 0;
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim(text.substr(start, end - start));
    ++number;
    start = end + 1;
    if (line.empty() || line.front() == '#') continue;
    // "name:token"; a token alone is named by its line (the log never shows a token).
    const auto colon = line.find(':');
    std::string name = colon == std::string_view::npos ? fmt::format("token {}", number)
                                                       : std::string(trim(line.substr(0, colon)));
    const std::string_view token = colon == std::string_view::npos ? line : trim(line.substr(colon + 1));
    if (token.empty()) continue;
    set.entries_.push_back({std::move(name), sha256(token)});
  }
  return set;
}

Result<TokenSet> TokenSet::load(const std::filesystem::path& path, std::string_view key) {
  if (auto ok = check_private_file(path, key); !ok) return ok.error();
  auto text = read_text_file(path);
  if (!text) return Error{fmt::format("{} {}: {}", key, path.string(), text.error().message)};
  TokenSet set = from_lines(*text);
  if (set.entries_.empty())
    return Error{fmt::format("{} {}: no token in it (one a line, \"token\" or \"name:token\")", key, path.string())};
  for (const auto& e : set.entries_)
    if (e.name.empty()) return Error{fmt::format("{} {}: a \"name:token\" line without a name", key, path.string())};
  return set;
}

std::optional<std::string> TokenSet::match(std::string_view token) const {
  // Digests are equal in length whatever was sent; every entry is compared
  // and the loop has no early exit.
  const auto digest = sha256(token);
  const Entry* found = nullptr;
  for (const auto& e : entries_) {
    const bool same = CRYPTO_memcmp(e.digest.data(), digest.data(), digest.size()) == 0;
    if (same && found == nullptr) found = &e;
  }
  if (found == nullptr || token.empty()) return std::nullopt;
  return found->name;
}

std::optional<std::string> auth_token_of(std::string_view line) {
  const auto json = nlohmann::json::parse(line, nullptr, false);
  if (!json.is_object()) return std::nullopt;
  const auto command = json.find("command");
  const auto token = json.find("token");
  if (command == json.end() || *command != "auth" || token == json.end() || !token->is_string()) return std::nullopt;
  return token->get<std::string>();
}

std::optional<std::uint64_t> LogLimiter::admit(std::chrono::steady_clock::time_point now) {
  if (last_ && now - *last_ < every_) {
    ++held_;
    return std::nullopt;
  }
  last_ = now;
  return std::exchange(held_, 0);
}

}  // namespace spinewatch

#include "access/pseudonym.hpp"
#include "support/station_dirs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>

#include "access/access.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {
namespace {

std::string hex(const unsigned char* data, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += fmt::format("{:02x}", data[i]);
  return out;
}

// O_EXCL: two daemons starting at once cannot both write a secret.
Status create_secret(const std::filesystem::path& path, std::string_view key) {
  unsigned char bytes[32];
  if (RAND_bytes(bytes, sizeof bytes) != 1) return Error{fmt::format("{}: no random bytes from OpenSSL", key)};
  const std::string text = hex(bytes, sizeof bytes) + "\n";
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return Error{fmt::format("{} {}: cannot create it: {}", key, path.string(), std::strerror(errno))};
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!written) return Error{fmt::format("{} {}: cannot write it: {}", key, path.string(), std::strerror(errno))};
  return Ok{};
}

}  // namespace

Result<Pseudonyms> Pseudonyms::open(const std::filesystem::path& path, std::string_view key) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    if (auto made = create_secret(path, key); !made) return made.error();
  }
  if (auto ok = check_private_file(path, key); !ok) return ok.error();
  auto text = read_text_file(path, 4096);
  if (!text) return Error{fmt::format("{} {}: {}", key, path.string(), text.error().message)};
  std::string secret = *text;
  while (!secret.empty() && (secret.back() == '\n' || secret.back() == '\r')) secret.pop_back();
  if (secret.size() != 64 || secret.find_first_not_of("0123456789abcdef") != std::string::npos)
    return Error{fmt::format("{} {}: expected 64 lower-case hex digits (delete it to have a new one made; "
                             "the pseudonyms then change)", key, path.string())};
  return Pseudonyms(std::move(secret));
}

std::string Pseudonyms::of(std::string_view id) const {
  unsigned char mac[32];
  unsigned int size = 0;
  HMAC(EVP_sha256(), secret_.data(), static_cast<int>(secret_.size()), reinterpret_cast<const unsigned char*>(id.data()),
       id.size(), mac, &size);
  return "w-" + hex(mac, 6);
}

Result<std::filesystem::path> default_secret_path() {
  return default_station_file(StationDir::State, "pseudonym.key", "privacy.secret_file");
}

}  // namespace spinewatch

#include "spinewatch/frames/text_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace spinewatch {
namespace {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

Error cannot_open(const std::filesystem::path& path, int error) {
  return Error{fmt::format("{}: cannot open: {}", path.string(), std::strerror(error))};
}

}  // namespace

Result<std::string> read_text_file(const std::filesystem::path& path, std::size_t max_bytes) {
  const FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) return cannot_open(path, errno);
  struct stat st{};
  if (::fstat(fd.get(), &st) != 0) return cannot_open(path, errno);
  if (S_ISDIR(st.st_mode)) return cannot_open(path, EISDIR);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(fd.get(), buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return cannot_open(path, errno);
    if (n == 0) return text;
    if (text.size() + static_cast<std::size_t>(n) > max_bytes)
      return Error{fmt::format("{}: larger than {} bytes, not an input file of spinewatch", path.string(), max_bytes)};
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

}  // namespace spinewatch

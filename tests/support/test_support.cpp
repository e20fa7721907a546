#include "test_support.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace spinewatch::test {

TempDir::TempDir() {
  std::random_device rd;
  const auto base = std::filesystem::path(binary_dir()) / "test-tmp";
  std::filesystem::create_directories(base);
  for (int attempt = 0; attempt < 100; ++attempt) {
    // Built with a stream: GCC 12 warns falsely (-Wrestrict) on "t" + std::string at -O2.
    std::ostringstream name;
    name << 't' << ::getpid() << '-' << rd();
    auto candidate = base / name.str();
    if (std::filesystem::create_directory(candidate)) {
      path_ = candidate;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<nlohmann::json> read_ndjson(const std::filesystem::path& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

std::filesystem::path source_path(const std::string& relative) {
  return std::filesystem::path(source_dir()) / relative;
}

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error("free_port: socket failed");
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
                  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0;
  ::close(fd);
  if (!ok) throw std::runtime_error("free_port: no port on 127.0.0.1");
  return ntohs(a.sin_port);
}

CommandResult run_command(const std::string& command_line) {
  CommandResult result;
  const std::string full = command_line + " 2>&1";
  FILE* pipe = ::popen(full.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

CommandResult run_cli(const std::string& args) { return run_command(cli_path() + " " + args); }

Posture sample_tracking_posture() {
  Posture p;
  p.seq = 17;
  p.t_ns = 566666666;
  p.state = TrackingState::Tracking;
  SpinePose pose;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    pose[i].body_center = Eigen::Vector3d(-60.0 + double(i), 1450.0 - 28.0 * double(i), 0.5 * double(i));
    pose[i].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * double(i), Eigen::Vector3d::UnitZ()));
  }
  p.vertebrae = pose;
  p.neck = pose[kNeckIndex].body_center;
  p.waist = pose[kWaistIndex].body_center;
  p.fit.cost = 0.031;
  p.latency_us = 412;
  return p;
}

std::string validate_ndjson(const std::filesystem::path& file) {
  const auto script = source_path("tests/support/validate_ndjson.py");
  const auto schema_dir = source_path("docs");
  auto r = run_command("/usr/bin/python3 '" + script.string() + "' '" + schema_dir.string() + "' '" + file.string() + "'");
  return r.exit_code == 0 ? std::string() : (r.output.empty() ? "validator failed to run" : r.output);
}

}  // namespace spinewatch::test

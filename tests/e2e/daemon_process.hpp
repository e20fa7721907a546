#pragma once
// Runs the real spinewatchd for a test: output to a log file, signals, exit
// status with a timeout, and its VmRSS.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "test_support.hpp"

extern char** environ;

namespace spinewatch::test {

class DaemonProcess {
 public:
  DaemonProcess(const std::vector<std::string>& args, const std::filesystem::path& log) : log_(log) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~DaemonProcess() {
    if (pid_ > 0 && !status_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int signo) { ::kill(pid_, signo); }

  // The exit code, or nothing if it has not exited (or was killed) within the timeout.
  std::optional<int> wait_exit(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!status_) {
      int status = 0;
      const pid_t r = ::waitpid(pid_, &status, WNOHANG);
      if (r == pid_) status_ = status;
      else if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      else std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return WIFEXITED(*status_) ? std::optional<int>(WEXITSTATUS(*status_)) : std::nullopt;
  }
  bool running() {
    if (status_) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) status_ = status;
    return !status_;
  }

  long vm_rss_kb() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
  }
  std::string log() const {
    std::ifstream in(log_);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

 private:
  std::filesystem::path log_;
  pid_t pid_ = -1;
  std::optional<int> status_;
};

// Calls `connect` until it returns instead of throwing (the daemon may still
// be starting), while the daemon runs, for at most 15 s (scaled).
template <class Connect>
std::optional<std::invoke_result_t<Connect>> when_up(Connect connect, DaemonProcess& daemon) {
  using namespace std::chrono_literals;
  const auto deadline = std::chrono::steady_clock::now() + scaled(15s);
  while (std::chrono::steady_clock::now() < deadline && daemon.running()) {
    try {
      return connect();
    } catch (const std::exception&) {
      std::this_thread::sleep_for(20ms);
    }
  }
  return std::nullopt;
}

}  // namespace spinewatch::test

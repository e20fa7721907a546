#pragma once
// The daemon's network loop: one Boost.Asio io_context and the thread that
// runs it. Both servers (the posture stream's Publisher and the HTTP live
// view) accept and serve their clients on it; the daemon owns it and hands
// its io_context to each, so neither server owns or borrows the other's.
//
// Order: the servers stop (closing their clients on the running loop),
// then the loop stops, then the servers are destroyed. Their handlers
// refer to them, so the loop's thread must be joined before they go; the
// io_context itself outlives their sockets.
#include <string>
#include <thread>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>

namespace spinewatch::net {

class NetworkLoop {
 public:
  // Starts the thread; `name` begins what it logs (e.g. "network").
  explicit NetworkLoop(std::string name);
  ~NetworkLoop();  // stop()
  NetworkLoop(const NetworkLoop&) = delete;
  NetworkLoop& operator=(const NetworkLoop&) = delete;

  boost::asio::io_context& io() { return io_; }
  // Ends the loop and joins its thread; handlers still queued are not run
  // (they are destroyed with the io_context). Idempotent; from any thread
  // but the loop's own.
  void stop();

 private:
  std::string name_;
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::thread thread_;  // declared last: started once the rest exists
};

}  // namespace spinewatch::net

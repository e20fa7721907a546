#include "http/http_routes.hpp"

namespace spinewatch {
namespace {

// The value of `key` in a query string "a=1&action=stream", or nothing.
std::string_view query_value(std::string_view query, std::string_view key) {
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == key) return eq == std::string_view::npos ? std::string_view{} : pair.substr(eq + 1);
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return {};
}

}  // namespace

HttpRoute route_of(std::string_view target) {
  const auto q = target.find('?');
  const std::string_view path = target.substr(0, q);
  const std::string_view query = q == std::string_view::npos ? std::string_view{} : target.substr(q + 1);
  if (path == "/" || path == "/index.html") {
    const std::string_view action = query_value(query, "action");
    if (action == "stream") return HttpRoute::Stream;
    if (action == "snapshot") return HttpRoute::Snapshot;
    if (!action.empty()) return HttpRoute::NotFound;
    return HttpRoute::Page;
  }
  if (path == "/stream") return HttpRoute::Stream;
  if (path == "/snapshot") return HttpRoute::Snapshot;
  if (path == "/state") return HttpRoute::State;
  if (path == "/metrics") return HttpRoute::Metrics;
  if (path == "/background/relearn") return HttpRoute::RelearnBackground;
  return HttpRoute::NotFound;
}

std::string_view method_of(HttpRoute route) { return route == HttpRoute::RelearnBackground ? "POST" : "GET"; }

}  // namespace spinewatch

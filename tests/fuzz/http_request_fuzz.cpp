// The live view's request handling (daemon/src/http): the bytes a client
// sends, read as the session reads them (Beast's request parser with the
// server's header and body limits), then routed by route_of and checked
// against method_of. The route is compared with a reference written here
// in another way (split the query into pairs, look the path up in a table),
// and route_of also gets the raw input as a target: it must never fail,
// and must agree with the reference on every string.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include <boost/beast/http.hpp>

#include "fuzz_support.hpp"
#include "http/http_routes.hpp"

namespace {

using spinewatch::HttpRoute;

std::vector<std::string_view> split(std::string_view text, char sep) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t at = text.find(sep, start);
    parts.push_back(text.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start));
    if (at == std::string_view::npos) return parts;
    start = at + 1;
  }
}

HttpRoute reference_route(std::string_view target) {
  const std::size_t q = target.find('?');
  const std::string_view path = target.substr(0, q);
  const std::string_view query = q == std::string_view::npos ? std::string_view{} : target.substr(q + 1);
  if (path == "/" || path == "/index.html") {
    for (std::string_view pair : split(query, '&')) {
      const std::size_t eq = pair.find('=');
      if (pair.substr(0, eq) != "action") continue;
      const std::string_view value = eq == std::string_view::npos ? std::string_view{} : pair.substr(eq + 1);
      if (value.empty()) return HttpRoute::Page;
      if (value == "stream") return HttpRoute::Stream;
      if (value == "snapshot") return HttpRoute::Snapshot;
      return HttpRoute::NotFound;
    }
    return HttpRoute::Page;
  }
  static constexpr std::array<std::pair<std::string_view, HttpRoute>, 5> kPaths{{
      {"/stream", HttpRoute::Stream},
      {"/snapshot", HttpRoute::Snapshot},
      {"/state", HttpRoute::State},
      {"/metrics", HttpRoute::Metrics},
      {"/background/relearn", HttpRoute::RelearnBackground},
  }};
  for (const auto& [p, route] : kPaths)
    if (p == path) return route;
  return HttpRoute::NotFound;
}

void check_route(std::string_view target) {
  const HttpRoute route = spinewatch::route_of(target);
  FUZZ_CHECK(route == reference_route(target), std::string(target));
  const std::string_view method = spinewatch::method_of(route);
  FUZZ_CHECK(method == "GET" || method == "POST", std::string(target));
  FUZZ_CHECK((method == "POST") == (route == HttpRoute::RelearnBackground), std::string(target));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace http = boost::beast::http;
  const std::string_view text = spinewatch::fuzz::as_text(data, size);
  check_route(text);

  // As HttpSession::read_request: header limit 8192 (HttpOptions::max_header_bytes), body 1024.
  http::request_parser<http::string_body> parser;
  parser.header_limit(8192);
  parser.body_limit(1024);
  parser.eager(true);
  boost::beast::error_code ec;
  std::string_view rest = text;
  while (!rest.empty() && !parser.is_done()) {
    const std::size_t used = parser.put(boost::asio::buffer(rest.data(), rest.size()), ec);
    if (ec == http::error::need_more) break;
    if (ec) return 0;  // the session answers 400/413/431 and closes
    if (used == 0) break;
    rest.remove_prefix(used);
  }
  if (!parser.is_header_done()) return 0;  // the session waits for the rest
  const auto& request = parser.get();
  const std::string_view target(request.target().data(), request.target().size());
  FUZZ_CHECK(!target.empty(), std::string(text.substr(0, 200)));
  FUZZ_CHECK(target.find_first_of("\r\n ") == std::string_view::npos, std::string(target));
  check_route(target);
  return 0;
}

#pragma once
// What each HTTP request target of the live view asks for (docs/interfaces.md
// §5), decided once per request; ustreamer's /?action=stream and
// /?action=snapshot are the same as /stream and /snapshot.
#include <string_view>

namespace spinewatch {

enum class HttpRoute {
  Page,               // GET /: the live view page
  Stream,             // GET /stream: MJPEG
  Snapshot,           // GET /snapshot: one JPEG
  State,              // GET /state: JSON
  Metrics,            // GET /metrics: Prometheus text
  RelearnBackground,  // POST /background/relearn
  NotFound,
};

// `target`: the request line's target, path and query ("/?action=stream").
HttpRoute route_of(std::string_view target);
// The method each route answers (GET also answers HEAD for the non-streaming routes).
std::string_view method_of(HttpRoute route);

}  // namespace spinewatch

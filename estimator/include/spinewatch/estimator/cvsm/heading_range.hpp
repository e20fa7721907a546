#pragma once
#include <cstdint>

namespace spinewatch {

// Which way the fit lets the subject face (config [cvsm] heading;
// docs/cvsm.md, "Heading"): facing the frontal camera, held there (the
// fit as it was before it had a heading); turned at most 90° either way
// from it, with a preference for facing it; or any way round the full
// circle, front told from back on converged fits of both sides, and not
// tracking while they cost about the same.
enum class HeadingRange : std::uint8_t { Fixed, Front, Any };

}  // namespace spinewatch

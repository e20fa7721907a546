#pragma once
#include <cstdint>

namespace spinewatch {

// Which way the fit lets the subject face (config [cvsm] heading;
// docs/cvsm.md, "Heading"): facing the frontal camera, held there (the
// fit as it was before it had a heading); turned at most 90° either way
// from it; or any way round the full circle. The silhouettes tell
// front from back only by a few per cent of their pixels, and a subject
// the model does not draw well (a box carried, a cluttered room) can make
// the wrong side cost less: a station whose worker faces the frontal
// camera is safer held to the front half.
enum class HeadingRange : std::uint8_t { Fixed, Front, Any };

}  // namespace spinewatch

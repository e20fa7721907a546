#pragma once
#include <cstdint>

namespace spinewatch {

// How the CVSM fit models the limbs and the head (config [cvsm] limbs):
// held where the template puts them (arms hanging, legs straight or
// seated), or articulated and searched per pair after the trunk
// (docs/cvsm.md, "Articulated limbs"); or held, with the arms searched
// only on the pairs where the held fit leaves a rise of its cost the arms
// explain (docs/cvsm.md, "Arms where the views show them").
enum class LimbMode : std::uint8_t { Fixed, Articulated, Auto };

}  // namespace spinewatch

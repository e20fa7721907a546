#pragma once
// fit.flag values that the estimator sets itself (the silhouette statuses
// are in silhouette.hpp); each documented in docs/protocol.md.
#include <string_view>

namespace spinewatch {

// A tracked pair whose silhouettes show an axial twist of the trunk whose
// sign the fit cannot tell (docs/cvsm.md, "Axial twist").
inline constexpr std::string_view kTwistUnresolvedFlag = "twist_unresolved";

// A pair whose silhouettes both end on an occluder's edge (a desk the
// background holds) above the floor: neither view sees the legs, so the
// waist is not pinned and the pair is lost (docs/cvsm.md, "Occluded lower
// body").
inline constexpr std::string_view kLowerBodyHiddenFlag = "lower_body_hidden";

}  // namespace spinewatch

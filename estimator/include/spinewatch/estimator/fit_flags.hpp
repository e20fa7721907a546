#pragma once
// fit.flag values that the estimator sets itself (the silhouette statuses
// are in silhouette.hpp); each documented in docs/protocol.md.
#include <string_view>

namespace spinewatch {

// A tracked pair whose silhouettes show an axial twist of the trunk whose
// sign the fit cannot tell (docs/cvsm.md, "Axial twist").
inline constexpr std::string_view kTwistUnresolvedFlag = "twist_unresolved";

}  // namespace spinewatch

#pragma once
// fit.flag values that the estimator and the daemon's pipeline set
// themselves (the silhouette statuses are in silhouette.hpp); each
// documented in docs/protocol.md.
#include <string_view>

namespace spinewatch {

// A tracked pair whose silhouettes show an axial twist of the trunk whose
// sign the fit cannot tell (docs/cvsm.md, "Axial twist").
inline constexpr std::string_view kTwistUnresolvedFlag = "twist_unresolved";

// A pair neither of whose views shows the pelvis: each silhouette ends on
// an occluder's edge (a desk the background holds) above the floor, or one
// does and the other ends on a seat it cannot tell from the person (a black
// chair), or each runs into an edge of the image with the fitted hips
// beyond it; the waist is not pinned and the pair is lost (docs/cvsm.md,
// "Occluded lower body", "A black chair", "Pelvis out of the picture").
inline constexpr std::string_view kLowerBodyHiddenFlag = "lower_body_hidden";

// The fitted head lies beyond an edge of the image in a view whose
// silhouette does not reach that edge: the person's head is in the
// picture and the model's is out of it, placed too high with its neck and
// shoulders where the head is, so the spine is drawn over the head; the
// pair is lost (docs/cvsm.md, "Head above the picture").
inline constexpr std::string_view kHeadBeyondImageFlag = "head_beyond_image";

// The subject turned his back to the frontal camera where [cvsm] heading
// ("fixed", "front") does not take that side: the fit would be his mirror
// image, so the pair is lost (docs/cvsm.md, "Turned away from the range").
inline constexpr std::string_view kFacingAwayFlag = "facing_away";

// A standing subject's pelvis well below where it stood: the knees are bent
// (a lunge, a squat), which the fixed limbs' straight legs cannot draw, so
// the waist's height is not pinned and the pair is lost (docs/cvsm.md, "A
// step aside").
inline constexpr std::string_view kKneesBentFlag = "knees_bent";

// With the legs held straight, a standing subject's silhouette shows legs
// below the waist that the model does not draw, while the fit leans the trunk
// sideways over them and explains the views worse than on the model's
// building: a step or a lunge read as a side bend, so the pair is lost
// (docs/cvsm.md, "Legs the fit leaves out").
inline constexpr std::string_view kLegsUnexplainedFlag = "legs_unexplained";

// The first pair to pass every check after pairs a check withheld while
// the fit went on from their pose (knees_bent, legs_unexplained, …): the
// search is still walking back from where those checks found it, so this
// pair is lost and the next one that passes is tracking (docs/cvsm.md,
// "Reacquired after a withheld stretch").
inline constexpr std::string_view kReacquiringFlag = "reacquiring";

// The pair that completes the subject's model fits it worse than the
// model's building did by more than a posture the model holds: the subject
// moved while the model was built (arms raised, a lunge), so this pair is
// lost and the next one that passes is held as reacquiring (docs/cvsm.md,
// "Provisional model").
inline constexpr std::string_view kMovedWhileBuildingFlag = "moved_while_building";

// Not a pair: a camera went away here; one lost posture marks the gap.
inline constexpr std::string_view kCameraLostFlag = "camera_lost";

// A stage of the estimator threw on this pair; it is reported lost.
inline constexpr std::string_view kEstimatorErrorFlag = "estimator_error";

}  // namespace spinewatch

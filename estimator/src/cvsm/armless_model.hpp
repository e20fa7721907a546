#pragma once
// The model the articulated trunk's search compares candidates on: the
// search model without its arms, so that the arms' outline, wherever they
// are, does not turn the trunk (docs/cvsm.md, "Arms where the views show
// them").
#include "spinewatch/estimator/cvsm/body_model.hpp"

namespace spinewatch::cvsm_detail {

// The model with the arms' chains left out (their planes stay, unused).
BodyModel without_arms(const BodyModel& model);

}  // namespace spinewatch::cvsm_detail

#pragma once
// One phantom recording through the whole per-pair estimator
// (PostureEstimator: silhouettes with their background lifecycle, the fit,
// the accurate model), as the scene-condition tests run it: what state
// every pair was published in, and how far each `tracking` posture's neck
// and waist are from the truth.
#include <algorithm>
#include <string>
#include <vector>

#include "phantom_run.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::test {

struct SceneRunStats {
  int pairs = 0;                  // pairs with the subject in view
  int tracking = 0, init = 0, lost = 0;
  int no_background = 0;          // init pairs flagged no_background
  int first_tracking = -1;        // person frame of the first tracking pair
  std::vector<double> neck, waist;  // mm, tracking pairs
  double worst = 0;               // mm, neck or waist, tracking pairs
  BackgroundCounts background;    // at the end
};

struct SceneRunOptions {
  bool stored_background = false;  // give the estimator the scene's empty images
  // The phantom's named subjects carry the generic spine (phantom_run.hpp).
  EstimatorOptions estimator = [] {
    EstimatorOptions o;
    o.subject.spine_placement = SpinePlacementMode::Generic;
    return o;
  }();
};

inline SceneRunStats run_scene(const phantom::PhantomSequence& seq, const SceneRunOptions& options = {}) {
  PostureEstimator estimator(seq.options().rig, options.estimator);
  if (options.stored_background) {
    // The empty scene as the phantom writes it: grey, or YUYV with colour.
    const SceneImage f = phantom::stored_background(seq, View::Frontal), l = phantom::stored_background(seq, View::Lateral);
    if (auto s = estimator.set_backgrounds(f.view(), l.view()); !s) throw std::runtime_error(s.error().message);
  }
  SceneRunStats st;
  for (int i = 0; i < seq.frame_count(); ++i) {
    const phantom::PhantomFrame f = seq.render(i);
    const Posture p = estimator.process(phantom::camera_pair(f));
    st.background = p.background;
    if (!f.truth.neck) continue;
    ++st.pairs;
    switch (p.state) {
      case TrackingState::Tracking: ++st.tracking; break;
      case TrackingState::Init:
        ++st.init;
        if (p.fit.flag && *p.fit.flag == "no_background") ++st.no_background;
        break;
      case TrackingState::Lost: ++st.lost; break;
    }
    if (p.state != TrackingState::Tracking || !p.neck || !p.waist) continue;
    if (st.first_tracking < 0) st.first_tracking = st.pairs - 1;
    st.neck.push_back((*p.neck - *f.truth.neck).norm());
    st.waist.push_back((*p.waist - *f.truth.waist).norm());
    st.worst = std::max({st.worst, st.neck.back(), st.waist.back()});
  }
  return st;
}

}  // namespace spinewatch::test

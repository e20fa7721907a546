#pragma once
// One phantom run through the CVSM, as the accuracy test and the seed
// sweep (accuracy_sweep.cpp) both make it: a subject unlike the generic
// model (config/subjects/<name>.json) rendered in memory, silhouettes
// learnt from the empty frames, the fit frame by frame, and the neck (T1
// body centre) and waist (L5 body centre) against the ground truth.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "test_support.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::test {

// Person frames per scenario: 10 init frames and a smooth movement. The
// same under the sanitizers (≈ 13 s CPU there for all scenarios): a
// shorter run would be a faster movement, i.e. a different test. `fast`
// keeps its absolute timing.
inline int person_frames(std::string_view scenario) { return scenario == "fast" ? 60 : 66; }

struct PhantomRunStats {
  std::vector<double> neck, waist;  // mm, valid person frames
  Eigen::Vector3d neck_bias = Eigen::Vector3d::Zero(), waist_bias = Eigen::Vector3d::Zero();  // mean signed error
  int person_frames = 0, lost = 0, longest_lost_run = 0;
  bool tracking_at_end = false;
};

inline double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), std::ceil(p * static_cast<double>(v.size())) - 1));
  return v[k];
}
inline double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

// The phantom's named subjects (config/subjects/*.json) carry the generic
// spine, at its fixed fractions of stature; the fit is scored on them with
// the same placement (how well the outline is followed). How well the
// spine is placed in measured people is tests/tools/population's.
inline CvsmOptions generic_subject_options() {
  CvsmOptions o;
  o.spine_placement = SpinePlacementMode::Generic;
  return o;
}

// The phantom's sensor noise is drawn from `seed` (the test uses 3).
inline Result<PhantomRunStats> run_phantom(const std::string& scenario, const std::string& subject_name, unsigned seed,
                                           const CvsmOptions& options = generic_subject_options()) {
  auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/" + subject_name + ".json");
  if (!subject.ok()) return subject.error();
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = *subject;
  po.frames = person_frames(scenario);
  po.seed = seed;
  auto seq = phantom::PhantomSequence::create(po);
  if (!seq.ok()) return seq.error();

  // The estimator sees only the images and the calibration.
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(po.rig, options);
  PhantomRunStats st;
  int run_length = 0;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const SilhouetteResult sf = frontal.extract(view_of(f.luma[0]));
    const SilhouetteResult sl = lateral.extract(view_of(f.luma[1]));
    const CvsmResult r = tracker.track(sf, sl);
    if (!f.truth.neck) continue;  // an empty frame
    ++st.person_frames;
    if (!r.valid()) {
      ++st.lost;
      st.longest_lost_run = std::max(st.longest_lost_run, ++run_length);
      st.tracking_at_end = false;
      continue;
    }
    run_length = 0;
    st.tracking_at_end = r.state == TrackingState::Tracking;
    st.neck.push_back((r.neck - *f.truth.neck).norm());
    st.waist.push_back((r.waist - *f.truth.waist).norm());
    st.neck_bias += r.neck - *f.truth.neck;
    st.waist_bias += r.waist - *f.truth.waist;
  }
  if (!st.neck.empty()) {
    st.neck_bias /= static_cast<double>(st.neck.size());
    st.waist_bias /= static_cast<double>(st.waist.size());
  }
  return st;
}

}  // namespace spinewatch::test

#include "spinewatch/population/sweep.hpp"

#include <algorithm>
#include <cmath>

#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "spinewatch/population/selection.hpp"

namespace spinewatch::population {

Result<Run> run_subject(const anthropometry::AnsurSubject& row, const std::string& scenario, const SweepOptions& o) {
  auto subject = phantom::subject_from_ansur(row, o.rules);
  if (!subject) return subject.error();
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = std::move(subject).value();
  if (o.frames > 0) po.frames = o.frames;
  po.empty_frames = o.empty_frames;
  // A seed per subject: textures, noise and joint factors differ between people.
  po.seed = o.seed + static_cast<std::uint32_t>(row.id);
  auto seq = phantom::PhantomSequence::create(po);
  if (!seq) return seq.error();

  Run run;
  run.subject_id = row.id;
  run.sex = row.sex;
  run.stature_mm = row.stature_mm;
  run.bmi = bmi(row);
  run.scenario = scenario;
  EstimatorOptions estimator_options = o.estimator;
  if (o.known_worker || o.known_landmarks) set_known_worker(estimator_options.subject, {row.stature_mm, row.mass_kg});
  if (o.known_landmarks) {
    estimator_options.subject.c7_height_mm = row.cervicale_height_mm;
    estimator_options.subject.iliac_crest_height_mm = row.iliocristale_height_mm;
  }
  PostureEstimator estimator(seq->options().rig, estimator_options);
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const Posture p = estimator.process(phantom::grey_pair(f));
    if (!f.truth.neck || !f.truth.vertebrae) continue;
    ++run.frames;
    if (p.state == TrackingState::Init) ++run.init;
    if (p.state == TrackingState::Lost) ++run.lost;
    if (p.state != TrackingState::Tracking || !p.neck || !p.waist || !p.vertebrae) continue;
    ++run.tracking;
    run.neck.push_back((*p.neck - *f.truth.neck).norm());
    run.waist.push_back((*p.waist - *f.truth.waist).norm());
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      run.delta[k].push_back((*p.vertebrae)[k].body_center - (*f.truth.vertebrae)[k].body_center);
  }
  if (const BodyModel* model = estimator.last_trace().body_model)
    run.model_height_mm = model->shape.stature_mm > 0 ? model->shape.stature_mm : model->shape.height_mm;
  return run;
}

Pooled pool(const std::vector<Run>& runs) {
  Pooled p;
  std::vector<double> neck, waist, all, stature;
  std::array<std::vector<double>, kVertebraCount> level;
  std::array<Eigen::Vector3d, kVertebraCount> sum;
  sum.fill(Eigen::Vector3d::Zero());
  double stature_sum = 0;
  for (const Run& r : runs) {
    ++p.runs;
    p.frames += r.frames;
    p.tracking += r.tracking;
    p.init += r.init;
    p.lost += r.lost;
    neck.insert(neck.end(), r.neck.begin(), r.neck.end());
    waist.insert(waist.end(), r.waist.begin(), r.waist.end());
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      for (const Eigen::Vector3d& d : r.delta[k]) {
        level[k].push_back(d.norm());
        all.push_back(d.norm());
        sum[k] += d;
      }
    // Seated, the stature is not seen (only the crown above the seat).
    if (r.model_height_mm > 0 && r.scenario.rfind("seated", 0) != 0) {
      stature.push_back(std::abs(r.model_height_mm - r.stature_mm));
      stature_sum += r.model_height_mm - r.stature_mm;
    }
  }
  p.neck = summarise(neck);
  p.waist = summarise(waist);
  p.vertebrae = summarise(all);
  for (std::size_t k = 0; k < kVertebraCount; ++k) {
    p.per_level[k] = summarise(level[k]);
    p.bias[k] = level[k].empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(sum[k] / double(level[k].size()));
    p.worst_level_mean = std::max(p.worst_level_mean, p.per_level[k].mean);
    p.worst_bias = std::max(p.worst_bias, p.bias[k].cwiseAbs().maxCoeff());
  }
  p.stature_abs = summarise(stature);
  p.stature_bias = stature.empty() ? 0 : stature_sum / double(stature.size());
  return p;
}

}  // namespace spinewatch::population

// CVSM speed: the whole per-pair silhouettes + fit on a tracked bend, and
// the fixed-point cost evaluation against the OpenCV float reference on
// the same candidates.
#include <array>
#include <cmath>
#include <optional>
#include <random>

#include <benchmark/benchmark.h>
#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "cvsm/silhouette_edges.hpp"
#include "cvsm/xor_cost.hpp"
#include "cvsm_reference.hpp"
#include "silhouette/threshold_row.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
namespace {

constexpr int kW = 320, kH = 240;

BodyModel subject() {
  BodyShape shape;
  shape.height_mm = 1620;
  shape.width_scale = 0.9;
  return build_body_model(generic_cvsm_spec(), generic_spine_spec(), shape,
                          {10, generic_spine_spec().l5_height_fraction * 1620, 0});
}

CvsmPose bend(double s) {
  CvsmPose p;
  p.flexion = 50 * s * 2 / 3;
  p.pelvis_flexion = 50 * s / 3;
  p.lateral = 10 * s;
  p.twist = 5 * s;
  return p;
}

cv::Mat background() {
  cv::Mat bg(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(140 + 50 * x / kW + 10 * ((x / 8 + y / 8) % 2));
  return bg;
}

cv::Mat frame(const cv::Mat& bg, const cv::Mat& person, std::mt19937& rng, double gain) {
  std::normal_distribution<double> noise(0, 2);
  cv::Mat out(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      out.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(gain * (person.at<std::uint8_t>(y, x) ? 60 : bg.at<std::uint8_t>(y, x)) + noise(rng));
  return out;
}

LumaView view(const cv::Mat& m) { return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

// Phantom frames: the petite subject (unlike the generic model) bending
// 0 → 50° → 0; background learnt from the empty frames, the subject model
// from the first person frames, then the tracked bend played back and forth
// (ping-pong, so the loop never jumps).
// With colour, the frames as the cameras deliver them: YUYV.
struct PhantomPairs {
  phantom::PhantomOptions options;
  std::vector<phantom::PhantomFrame> frames;
  std::vector<std::array<std::vector<std::uint8_t>, 2>> yuyv;
  LumaView view_of(std::size_t i, int v) const {
    if (yuyv.empty()) return view(frames[i].luma[static_cast<std::size_t>(v)]);
    return {yuyv[i][static_cast<std::size_t>(v)].data(), kW, kH, 2 * kW, 2};
  }
};
std::optional<PhantomPairs> flexion_pairs(benchmark::State& state, bool colour, const char* scenario = "flexion") {
  PhantomPairs p;
  p.options.scenario = scenario;
  p.options.colour = colour;
  auto subject = phantom::load_subject(std::string(SPINEWATCH_SOURCE_DIR) + "/config/subjects/petite.json");
  if (!subject.ok()) {
    state.SkipWithError(subject.error().message.c_str());
    return std::nullopt;
  }
  p.options.subject = *subject;
  p.options.frames = 90;
  auto seq = phantom::PhantomSequence::create(p.options);
  if (!seq.ok()) {
    state.SkipWithError(seq.error().message.c_str());
    return std::nullopt;
  }
  for (int i = 0; i < seq->frame_count(); ++i) {
    p.frames.push_back(seq->render(i));
    if (colour) p.yuyv.push_back({phantom::yuyv_bytes(p.frames.back(), 0), phantom::yuyv_bytes(p.frames.back(), 1)});
  }
  return p;
}

// With `lifecycle`, what the estimator does around the fit since the
// background lifecycle: the silhouettes gated by the last fit's outline,
// the fitted outline rendered and grown, both backgrounds adapted.
void pair_silhouettes_and_fit(benchmark::State& state, bool lifecycle, bool colour = false,
                              const char* scenario = "flexion", const CvsmOptions& options = {}) {
  auto pairs = flexion_pairs(state, colour, scenario);
  if (!pairs) return;
  const auto& frames = pairs->frames;
  SilhouetteExtractor extractors[2] = {SilhouetteExtractor{SilhouetteOptions{}}, SilhouetteExtractor{SilhouetteOptions{}}};
  CvsmTracker tracker(pairs->options.rig, options);
  BitMask fitted[2], gates[2] = {BitMask(kW, kH), BitMask(kW, kH)};
  bool gated = false;
  auto one_pair = [&](std::size_t i) {
    SilhouetteResult s[2];
    for (int v = 0; v < 2; ++v) s[v] = extractors[v].extract(pairs->view_of(i, v), gated ? &gates[v] : nullptr);
    const CvsmResult r = tracker.track(s[0], s[1]);
    if (lifecycle) {
      gated = r.state == TrackingState::Tracking;
      for (int v = 0; v < 2; ++v) {
        fitted[v] = gated ? tracker.fitted_mask(kViews[v]) : BitMask{};
        gated = gated && !fitted[v].empty();
        if (gated) dilate_square(fitted[v], 16, gates[v]);
        extractors[v].adapt(pairs->view_of(i, v), gated ? &fitted[v] : nullptr);
      }
    }
    return r;
  };
  const int first_tracked = pairs->options.empty_frames + CvsmOptions{}.subject_frames;
  for (int i = 0; i < first_tracked; ++i) one_pair(static_cast<std::size_t>(i));
  const int n = static_cast<int>(frames.size()) - first_tracked;
  int k = 0, lost = 0;
  std::int64_t candidates = 0, count = 0;
  for (auto _ : state) {
    const int phase = k++ % (2 * n - 2);
    const CvsmResult r = one_pair(static_cast<std::size_t>(first_tracked + (phase < n ? phase : 2 * n - 2 - phase)));
    lost += r.state == TrackingState::Lost;
    candidates += r.fit.candidates.value_or(0);
    ++count;
    benchmark::DoNotOptimize(r.waist);
  }
  state.counters["lost"] = lost;
  state.counters["candidates"] = count > 0 ? static_cast<double>(candidates) / static_cast<double>(count) : 0.0;
}

double median_of(const std::vector<double>& v) {
  std::vector<double> s = v;
  std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
  return s[s.size() / 2];
}

void BM_PairSilhouettesAndFit(benchmark::State& state) { pair_silhouettes_and_fit(state, false); }
void BM_PairWithBackgroundLifecycle(benchmark::State& state) { pair_silhouettes_and_fit(state, true); }
BENCHMARK(BM_PairWithBackgroundLifecycle)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);
// The same with the cameras in colour (YUYV chroma, the colour threshold).
void BM_PairColourWithBackgroundLifecycle(benchmark::State& state) { pair_silhouettes_and_fit(state, true, true); }
BENCHMARK(BM_PairColourWithBackgroundLifecycle)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);


BENCHMARK(BM_PairSilhouettesAndFit)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);
// The `twist` scenario (±20°): most pairs beyond 6° of twist, where the
// tracker also scores the mirrored twist (docs/cvsm.md, "Axial twist").
void BM_PairSilhouettesAndFitTwist(benchmark::State& state) { pair_silhouettes_and_fit(state, false, false, "twist"); }
BENCHMARK(BM_PairSilhouettesAndFitTwist)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);
// The same with the outline refinement off (config [cvsm] refine_steps = 0)
// and with two steps (one, the default, is BM_PairSilhouettesAndFit).
void BM_PairSilhouettesAndFitRefineSteps(benchmark::State& state) {
  CvsmOptions options;
  options.refine_steps = static_cast<int>(state.range(0));
  pair_silhouettes_and_fit(state, false, false, "flexion", options);
}
BENCHMARK(BM_PairSilhouettesAndFitRefineSteps)->Arg(0)->Arg(2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);
// The same with articulated limbs (config [cvsm] limbs = "articulated";
// "auto" by default): the trunk's search, the limbs' (trunk held), the
// trunk's again (docs/cvsm.md, "Articulated limbs").
void BM_PairSilhouettesAndFitArticulatedLimbs(benchmark::State& state) {
  CvsmOptions options;
  options.limbs = LimbMode::Articulated;
  pair_silhouettes_and_fit(state, false, false, "flexion", options);
}
BENCHMARK(BM_PairSilhouettesAndFitArticulatedLimbs)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);
// Auto limbs (config [cvsm] limbs = "auto"): the fixed fit, and the arms'
// search where its cost rises (docs/cvsm.md, "Arms where the views show
// them"). /0: fixed limbs on `arms_overhead`; /1: auto on `arms_overhead`
// (the arms searched on most pairs); /2: auto on `flexion` (never engaged).
void BM_PairSilhouettesAndFitAutoLimbs(benchmark::State& state) {
  CvsmOptions options;
  options.limbs = state.range(0) == 0 ? LimbMode::Fixed : LimbMode::Auto;
  pair_silhouettes_and_fit(state, false, false, state.range(0) == 2 ? "flexion" : "arms_overhead", options);
}
BENCHMARK(BM_PairSilhouettesAndFitAutoLimbs)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("median", median_of);

// A block-shaped person over the background, 2 % brighter exposure.
cv::Mat block_person_frame(const cv::Mat& bg, unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat person(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(person, cv::Rect(130, 30, 60, 210), 255, cv::FILLED);
  return frame(bg, person, rng, 1.02);
}

void BM_SilhouettesOnly(benchmark::State& state) {
  const cv::Mat bg = background();
  const cv::Mat f = block_person_frame(bg, 2);
  SilhouetteOptions so;
  so.background = BackgroundMode::Image;
  SilhouetteExtractor ex(so);
  (void)ex.set_background(view(bg));
  for (auto _ : state) benchmark::DoNotOptimize(ex.extract(view(f)).pixels);
}
BENCHMARK(BM_SilhouettesOnly)->Unit(benchmark::kMicrosecond);

// One view's background adaptation pass (a sixteenth of the rows), with a
// person and their margin left out.
void BM_BackgroundAdapt(benchmark::State& state) {
  const cv::Mat bg = background();
  const cv::Mat f = block_person_frame(bg, 5);
  SilhouetteExtractor ex{SilhouetteOptions{}};
  (void)ex.set_background(view(bg));
  (void)ex.extract(view(f));
  for (auto _ : state) ex.adapt(view(f));
  benchmark::DoNotOptimize(ex.background().data());
}
BENCHMARK(BM_BackgroundAdapt)->Unit(benchmark::kMicrosecond);

// The per-pixel test of a whole 320×240 frame into bits: SSE2 against its
// scalar reference (arg 0: reference, 1: fast path).
void BM_ThresholdFrame(benchmark::State& state) {
  const cv::Mat bg = background();
  const cv::Mat f = block_person_frame(bg, 4);
  BitMask out(kW, kH);
  silhouette_detail::ThresholdRow row;
  row.gain_q7 = silhouette_detail::gain_to_q7(1.02);
  row.width = kW;
  const bool fast = state.range(0) == 1;
  for (auto _ : state) {
    for (int y = 0; y < kH; ++y) {
      row.frame = f.ptr<std::uint8_t>(y);
      row.background = bg.ptr<std::uint8_t>(y);
      if (fast)
        silhouette_detail::threshold_row(row, out.row(y));
      else
        silhouette_detail::threshold_row_reference(row, out.row(y));
    }
    benchmark::DoNotOptimize(out.row(0)[0]);
  }
}
BENCHMARK(BM_ThresholdFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The colour test of a whole YUYV frame (a beige wall, a blue block, a
// shadow beside it): SSE2 against its scalar reference (arg 0 / 1).
void BM_ThresholdColourFrame(benchmark::State& state) {
  const cv::Mat bg = background();
  const cv::Mat f = block_person_frame(bg, 4);
  std::vector<std::uint8_t> frame(static_cast<std::size_t>(2 * kW * kH)), chroma(static_cast<std::size_t>(kW * kH));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const auto i = static_cast<std::size_t>(y * kW + x);
      const bool person = x >= 130 && x < 190 && y >= 30;
      const bool shadow = !person && x >= 190 && x < 220 && y >= 60;
      chroma[i] = static_cast<std::uint8_t>(x % 2 ? 142 : 118);
      frame[2 * i] = shadow ? static_cast<std::uint8_t>(f.at<std::uint8_t>(y, x) * 2 / 3) : f.at<std::uint8_t>(y, x);
      frame[2 * i + 1] = person ? static_cast<std::uint8_t>(x % 2 ? 112 : 150) : shadow ? static_cast<std::uint8_t>(x % 2 ? 137 : 121) : chroma[i];
    }
  BitMask out(kW, kH);
  silhouette_detail::ThresholdRow row;
  row.gain_q7 = silhouette_detail::gain_to_q7(1.02);
  row.width = kW;
  row.frame_step = 2;
  const bool fast = state.range(0) == 1;
  for (auto _ : state) {
    for (int y = 0; y < kH; ++y) {
      row.frame = frame.data() + static_cast<std::ptrdiff_t>(y) * 2 * kW;
      row.background = bg.ptr<std::uint8_t>(y);
      row.chroma_background = chroma.data() + static_cast<std::ptrdiff_t>(y) * kW;
      if (fast)
        silhouette_detail::threshold_row(row, out.row(y));
      else
        silhouette_detail::threshold_row_reference(row, out.row(y));
    }
    benchmark::DoNotOptimize(out.row(0)[0]);
  }
}
BENCHMARK(BM_ThresholdColourFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

struct Candidates {
  CameraRig rig = CameraRig::default_rig();
  BodyModel body = subject();
  BitMask sf, sl;
  cv::Mat mf, ml;
  std::vector<std::vector<Eigen::Vector3d>> points;
  Candidates() {
    std::vector<Eigen::Vector3d> pts;
    control_points(body, pose_vertebrae(body, generic_spine_spec(), bend(0.5)), pts);
    mf = cv::Mat(kH, kW, CV_8U);
    ml = cv::Mat(kH, kW, CV_8U);
    test::render_reference(rig.frontal, body, pts, mf);
    test::render_reference(rig.lateral, body, pts, ml);
    sf = test::to_mask(mf);
    sl = test::to_mask(ml);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> s(0.3, 0.7), t(-20, 20);
    for (int i = 0; i < 64; ++i) {
      CvsmPose p = bend(s(rng));
      p.translation = {t(rng), 0, t(rng)};
      control_points(body, pose_vertebrae(body, generic_spine_spec(), p), pts);
      points.push_back(pts);
    }
  }
};

void BM_CostFixedPoint(benchmark::State& state) {
  Candidates c;
  XorCost cost(c.rig, kW, kH);
  cost.set_silhouettes(c.sf, c.sl);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cost.evaluate(c.body, c.points[i++ % c.points.size()]).total());
}
BENCHMARK(BM_CostFixedPoint)->Unit(benchmark::kMicrosecond);

// What one search candidate costs the tracker: the same candidates on the
// outline it searches with (every 4th vertebra ring, every 4th row; the
// defaults of CvsmOptions). Not comparable with the reference, which
// draws every ring on every row.
void BM_CostSearchCandidate(benchmark::State& state) {
  Candidates c;
  const CvsmOptions defaults;
  const BodyModel thin = thin_trunk(c.body, defaults.search_vertebra_step);
  XorCost cost(c.rig, kW, kH);
  cost.set_silhouettes(c.sf, c.sl);
  cost.set_row_step(defaults.search_row_step);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cost.evaluate(thin, c.points[i++ % c.points.size()]).total());
}
BENCHMARK(BM_CostSearchCandidate)->Unit(benchmark::kMicrosecond);

// A subject's body model built from the generic model file's parts: done
// for every candidate shape while the subject model is refined (init).
// Its reference is the model's own tests (BodyModel.*, the control points'
// order and values).
void BM_BuildBodyModel(benchmark::State& state) {
  const CvsmSpec& spec = generic_cvsm_spec();
  const SpineSpec& spine = generic_spine_spec();
  BodyShape shape;
  shape.height_mm = 1620;
  shape.width_scale = 0.9;
  const Eigen::Vector3d l5(10, spine.l5_height_fraction * 1620, 0);
  for (auto _ : state) {
    BodyModel model = build_body_model(spec, spine, shape, l5);
    benchmark::DoNotOptimize(model.local_points.data());
  }
}
BENCHMARK(BM_BuildBodyModel)->Unit(benchmark::kMicrosecond);

// The model's control points at a pose (the pose already through the
// spine's kinematics): the limbs neutral (arg 0, as without
// articulation) and all turned (arg 1, the joints' chain).
void BM_ControlPoints(benchmark::State& state) {
  const BodyModel body = subject();
  const SpinePose v = pose_vertebrae(body, generic_spine_spec(), bend(0.5));
  LimbPose limbs;
  if (state.range(0) != 0) {
    for (auto& side : limbs.side) side = {30, 20, 40, 20, 10, 30};
    limbs.head_flexion = limbs.head_lateral = limbs.head_turn = 10;
  }
  std::vector<Eigen::Vector3d> pts;
  for (auto _ : state) {
    control_points(body, v, pts, limbs);
    benchmark::DoNotOptimize(pts.data());
  }
}
BENCHMARK(BM_ControlPoints)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// What one candidate of the limbs' search costs: the trunk held, one
// joint's angle changed per candidate (the incremental cache projects and
// scans only that limb's rings and segments again), on the search's
// outline and rows.
void BM_CostLimbCandidate(benchmark::State& state) {
  Candidates c;
  const CvsmOptions defaults;
  const BodyModel thin = thin_trunk(c.body, defaults.search_vertebra_step);
  XorCost cost(c.rig, kW, kH);
  cost.set_silhouettes(c.sf, c.sl);
  cost.set_row_step(defaults.search_row_step);
  const SpinePose v = pose_vertebrae(c.body, generic_spine_spec(), bend(0.5));
  std::vector<std::vector<Eigen::Vector3d>> candidates;
  for (int i = 0; i < 32; ++i) {
    LimbPose limbs;
    const double a = (i % 2 ? 6.0 : -6.0);
    switch (i % 4) {
      case 0: limbs.side[static_cast<std::size_t>(i / 4 % 2)].shoulder_flexion = a; break;
      case 1: limbs.side[static_cast<std::size_t>(i / 4 % 2)].elbow = a; break;
      case 2: limbs.side[static_cast<std::size_t>(i / 4 % 2)].hip_flexion = a; break;
      default: limbs.head_flexion = a; break;
    }
    std::vector<Eigen::Vector3d> pts;
    control_points(thin, v, pts, limbs);
    candidates.push_back(std::move(pts));
  }
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cost.evaluate(thin, candidates[i++ % candidates.size()]).total());
}
BENCHMARK(BM_CostLimbCandidate)->Unit(benchmark::kMicrosecond);

// What the outline refinement's passes cost on the full model, every other
// row (CvsmOptions::refine_row_step), against a whole-pixel evaluation of
// the same (arg 0): the outline's ends of both views (arg 1, a trial
// step's pass) and a scan conversion only (arg 2, a derivative's pass).
void BM_CostRefinePass(benchmark::State& state) {
  Candidates c;
  XorCost cost(c.rig, kW, kH);
  cost.set_silhouettes(c.sf, c.sl);
  cost.set_row_step(CvsmOptions{}.refine_row_step);
  std::vector<cvsm_detail::OutlineEnd> ends;
  std::size_t i = 0;
  if (state.range(0) == 0)
    for (auto _ : state) benchmark::DoNotOptimize(cost.evaluate(c.body, c.points[i++ % c.points.size()]).total());
  else if (state.range(0) == 1)
    for (auto _ : state) benchmark::DoNotOptimize(cost.outline(c.body, c.points[i++ % c.points.size()], ends));
  else
    for (auto _ : state) benchmark::DoNotOptimize(cost.scan(c.body, c.points[i++ % c.points.size()]));
}
BENCHMARK(BM_CostRefinePass)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// The outline refinement's edge lookup: the nearest silhouette edge of a
// kind to a point of a row, as the refinement asks it once per outline end
// (about a thousand a pass), on the phantom's frontal silhouette.
void BM_SilhouetteEdgeNearest(benchmark::State& state) {
  Candidates c;
  cvsm_detail::SilhouetteEdges edges;
  edges.assign(c.sf);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> x(0.0f, kW - 1.0f);
  std::vector<std::pair<int, float>> queries(1024);
  for (auto& q : queries) q = {static_cast<int>(rng() % kH), x(rng)};
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& q = queries[i++ & 1023];
    benchmark::DoNotOptimize(edges.nearest(q.first, q.second, (i & 1) != 0, 6));
  }
}
BENCHMARK(BM_SilhouetteEdgeNearest);

void BM_CostOpenCvReference(benchmark::State& state) {
  Candidates c;
  cv::Mat scratch, diff;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& pts = c.points[i++ % c.points.size()];
    benchmark::DoNotOptimize(test::reference_xor(c.rig.frontal, c.body, pts, c.mf, scratch, diff) +
                             test::reference_xor(c.rig.lateral, c.body, pts, c.ml, scratch, diff));
  }
}
BENCHMARK(BM_CostOpenCvReference)->Unit(benchmark::kMicrosecond);

// The distorted projection: a lens with distortion sends every control
// point of the fit through CameraModel::project (FixedCamera's fallback);
// 5 coefficients (what calibrate writes) and all 14 of OpenCV's model,
// against cv::projectPoints on the same points (the reference the camera
// tests compare with to 1e-6 px).
std::vector<Eigen::Vector3d> projection_points() {
  std::vector<Eigen::Vector3d> points;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-400, 400), h(300, 1900);
  for (int i = 0; i < 1024; ++i) points.emplace_back(u(rng), h(rng), u(rng));
  return points;
}

CameraModel lens(int coefficients) {
  CameraModel cam = CameraRig::default_rig().lateral;
  const double d[14] = {-0.21, 0.05, 0.001, -0.0007, 0.01, 0.02, -0.004, 0.001, 0.002, -0.001, 0.0015, 0.0003, 0.01, -0.008};
  for (int i = 0; i < coefficients; ++i) cam.dist_coeffs[static_cast<std::size_t>(i)] = d[i];
  return cam;
}

void BM_ProjectDistorted(benchmark::State& state) {
  const CameraModel cam = lens(static_cast<int>(state.range(0)));
  const auto points = projection_points();
  for (auto _ : state)
    for (const auto& p : points) benchmark::DoNotOptimize(cam.project(p));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size()));
}
BENCHMARK(BM_ProjectDistorted)->Arg(5)->Arg(14);

void BM_ProjectDistortedOpenCv(benchmark::State& state) {
  const CameraModel cam = lens(static_cast<int>(state.range(0)));
  std::vector<cv::Point3d> points;
  for (const auto& p : projection_points()) points.emplace_back(p.x(), p.y(), p.z());
  cv::Mat K, R, rvec, t;
  cv::eigen2cv(cam.camera_matrix, K);
  cv::eigen2cv(cam.R, R);
  cv::eigen2cv(cam.t, t);
  cv::Rodrigues(R, rvec);
  const std::vector<double> dist = cam.distortion();
  std::vector<cv::Point2d> out;
  for (auto _ : state) {
    cv::projectPoints(points, rvec, t, K, dist, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size()));
}
BENCHMARK(BM_ProjectDistortedOpenCv)->Arg(5)->Arg(14);

}  // namespace
}  // namespace spinewatch

BENCHMARK_MAIN();

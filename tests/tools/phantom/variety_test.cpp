// The phantom as varied as the world (docs/phantom.md): limbs, station
// geometry, rooms, furniture and compression, each changing what it should.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "spinewatch/estimator/units.hpp"
#include "spinewatch/phantom/compression.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

PhantomSequence make(PhantomOptions options) {
  auto sequence = PhantomSequence::create(std::move(options));
  if (!sequence) throw std::runtime_error(sequence.error().message);
  return std::move(sequence).value();
}
PhantomOptions short_run(const std::string& scenario, int frames = 9) {
  PhantomOptions o;
  o.scenario = scenario;
  o.frames = frames;
  o.empty_frames = 0;
  return o;
}

// The person layer's bounding box in one view.
cv::Rect extent(const PhantomFrame& frame, View view) { return cv::boundingRect(frame.person[static_cast<int>(view)] > 0); }

TEST(PhantomLimbs, LimbsAtRestDrawTheRestPose) {
  const BodyModel body(Subject{}, SubjectPosture::Standing, 3);
  const TrunkMotion trunk{.flexion_deg = 20, .lateral_deg = 5, .twist_deg = 4};
  const LimbMotion rest;
  const BodyPose a = body.pose(trunk), b = body.pose(trunk, &rest);
  ASSERT_EQ(a.solids.size(), b.solids.size());
  // The same parts, perhaps in another order: compare each part's centroid set.
  auto centroids = [](const BodyPose& p) {
    std::vector<std::array<double, 3>> out;
    for (const Solid& s : p.solids) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const auto& q : s.points) c += q;
      c /= double(s.points.size());
      out.push_back({c.x(), c.y(), c.z()});
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto ca = centroids(a), cb = centroids(b);
  for (std::size_t i = 0; i < ca.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ca[i][std::size_t(k)], cb[i][std::size_t(k)], 1e-9) << i;
}

TEST(PhantomLimbs, EveryLimbScenarioRendersAndItsLimbsMove) {
  struct Case {
    const char* name;
    int peak;  // the person frame (of 9) where the limbs are furthest from rest
  };
  for (const Case c : {Case{"reach", 6}, Case{"arms_overhead", 4}, Case{"carry", 4}, Case{"stride", 1}, Case{"lunge", 4},
                       Case{"typing", 4}}) {
    SCOPED_TRACE(c.name);
    const PhantomSequence seq = make(short_run(c.name));
    const PhantomFrame first = seq.render(0), peak = seq.render(c.peak);
    ASSERT_EQ(peak.truth.state, TrackingState::Tracking);
    ASSERT_GT(cv::countNonZero(peak.person[0]), 500);
    ASSERT_GT(cv::countNonZero(peak.person[1]), 500);
    const cv::Rect f0 = extent(first, View::Frontal), f1 = extent(peak, View::Frontal);
    const cv::Rect l0 = extent(first, View::Lateral), l1 = extent(peak, View::Lateral);
    const std::string name = c.name;
    if (name == "arms_overhead") {
      // The arms above the head (at the top of the image, in the frontal view).
      EXPECT_GT(cv::countNonZero(peak.person[0].rowRange(0, f0.y)), 150);
    }
    if (name == "reach") {
      EXPECT_GT(l1.br().x, l0.br().x + 15);                // forwards (image right in lateral)
    }
    if (name == "stride") {
      EXPECT_GT(l1.br().x, l0.br().x + 10);               // the knee up and forwards
    }
    if (name == "lunge") {
      EXPECT_GT(l1.width, l0.width + 40);                  // the legs apart, the arm out
    }
    if (name == "lunge") {
      EXPECT_LT(f1.y, f0.y - 10);                          // the far arm overhead
    }
    if (name == "carry") {
      EXPECT_GT(cv::countNonZero(peak.person[0] == kBoxShade), 300);  // the box, in the person
    }
    if (name == "typing") {
      EXPECT_NE(cv::countNonZero(first.person[1] != peak.person[1]), 0);
    }
  }
}

TEST(PhantomLimbs, TheStepAsideMovesTheBodyAndTheFeet) {
  const PhantomSequence seq = make(short_run("stride", 30));
  const PhantomFrame before = seq.render(18), after = seq.render(29);
  EXPECT_NEAR(after.truth.waist->z() - before.truth.waist->z(), 250, 5);
  // To the subject's right is image left in the frontal view: the whole
  // person, feet included, moves left.
  const cv::Rect b = extent(before, View::Frontal), a = extent(after, View::Frontal);
  EXPECT_LT(a.x, b.x - 20);
  EXPECT_LT(a.br().x, b.br().x - 20);
}

TEST(PhantomScene, TheDeskHidesTheLegsAndBelongsToTheRoom) {
  PhantomOptions with = short_run("typing", 3), without = with;
  without.desk = false;
  const PhantomSequence desk = make(with), bare = make(without);
  EXPECT_EQ(desk.furniture(), Furniture::Desk);
  EXPECT_EQ(bare.furniture(), Furniture::None);
  const PhantomFrame a = desk.render(1), b = bare.render(1);
  // The legs show below the desk top without it; with it, nothing of the person does.
  const cv::Rect ea = extent(a, View::Frontal), eb = extent(b, View::Frontal);
  EXPECT_LT(ea.br().y, eb.br().y - 30);
  // The waist (L5) is behind the desk from the frontal camera.
  const auto waist = desk.camera(View::Frontal).project(*a.truth.waist);
  ASSERT_TRUE(waist);
  const cv::Point w(int(std::lround(waist->x())), int(std::lround(waist->y())));
  EXPECT_EQ(a.person[0].at<std::uint8_t>(w), 0);
  EXPECT_NE(b.person[0].at<std::uint8_t>(w), 0);
  // The desk is in the empty scene (the stored background), not in the person layer.
  cv::Mat diff;
  cv::absdiff(desk.background(View::Frontal), bare.background(View::Frontal), diff);
  EXPECT_GT(cv::countNonZero(diff > 15), 5000);
  const cv::Mat desk_pixels = (diff > 15) & (a.person[0] > 0);
  EXPECT_LT(cv::countNonZero(desk_pixels), cv::countNonZero(a.person[0]) / 4);  // only the forearms lie over it
  // --desk puts a bench in front of a standing subject.
  PhantomOptions bench = short_run("upright", 1);
  bench.desk = true;
  EXPECT_EQ(make(bench).furniture(), Furniture::Bench);
}

TEST(PhantomScene, AChairIsUnderTheSeatedSubjectAndBelongsToTheRoom) {
  PhantomOptions bare_options = short_run("seated_flexion", 3), grey_options = bare_options, black_options = bare_options;
  grey_options.chair = Chair::Grey;
  black_options.chair = Chair::Black;
  const PhantomSequence bare = make(bare_options), grey = make(grey_options), black = make(black_options);
  const PhantomFrame b = bare.render(1), g = black.render(1);
  // The chair is in the empty scene (the stored background) of both views.
  // (The grey one's seat is the floor's grey from the side.)
  for (View view : kViews) {
    cv::Mat diff;
    cv::absdiff(black.background(view), bare.background(view), diff);
    EXPECT_GT(cv::countNonZero(diff > 15), 1000) << static_cast<int>(view);
    cv::absdiff(grey.background(view), bare.background(view), diff);
    EXPECT_GT(cv::countNonZero(diff > 15), 100) << static_cast<int>(view);
  }
  // The subject sits on it: seen from the side, the seat's top meets the
  // person's lowest outline under the hips, and the chair hides little of
  // the person (what sinks into the seat's cushion).
  const int lateral = static_cast<int>(View::Lateral);
  const auto waist = black.camera(View::Lateral).project(*g.truth.waist);
  ASSERT_TRUE(waist);
  const int column = static_cast<int>(std::lround(waist->x()));
  int lowest = -1;
  for (int y = 0; y < g.person[lateral].rows; ++y)
    if (g.person[lateral].at<std::uint8_t>(y, column)) lowest = y;
  ASSERT_GT(lowest, 0);
  cv::Mat seat_diff;
  cv::absdiff(black.background(View::Lateral), bare.background(View::Lateral), seat_diff);
  for (int dy = 1; dy <= 3; ++dy) EXPECT_GT(seat_diff.at<std::uint8_t>(lowest + dy, column), 15) << dy;
  const int hidden = cv::countNonZero((b.person[lateral] > 0) & (g.person[lateral] == 0));
  EXPECT_GT(hidden, 0);
  EXPECT_LT(hidden, cv::countNonZero(b.person[lateral]) / 10);
  // The black chair is darker than the trousers by less than the
  // silhouette's default threshold (28); the grey one lighter by more.
  const double black_seat = black.background(View::Lateral).at<std::uint8_t>(lowest + 2, column);
  const double grey_seat = grey.background(View::Lateral).at<std::uint8_t>(lowest + 2, column);
  EXPECT_GT(black_seat, kTrousersShade - 28);
  EXPECT_LT(black_seat, kTrousersShade);
  EXPECT_GT(grey_seat, kTrousersShade + 28);
  // A standing subject has no chair: the error says which scenarios do.
  PhantomOptions standing = short_run("upright", 1);
  standing.chair = Chair::Black;
  const auto refused = PhantomSequence::create(standing);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("seated scenario"), std::string::npos) << refused.error().message;
}

double mean_gradient(const cv::Mat& grey) {
  cv::Mat gx, gy, mag;
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, mag);
  return cv::mean(mag)[0];
}

TEST(PhantomScene, AClutteredRoomHasEdgesTheSubjectUnchanged) {
  PhantomOptions plain = short_run("upright", 1), cluttered = plain;
  cluttered.room = RoomKind::Cluttered;
  const PhantomSequence a = make(plain), b = make(cluttered);
  for (View view : kViews) {
    EXPECT_GT(mean_gradient(b.background(view)), 3 * mean_gradient(a.background(view)));
  }
  EXPECT_NE(cv::countNonZero(b.background(View::Frontal) != b.background(View::Lateral)), 0);
  // The room changes the scene, not the person.
  const PhantomFrame fa = a.render(0), fb = b.render(0);
  EXPECT_EQ(cv::countNonZero(fa.person[0] != fb.person[0]), 0);
}

TEST(PhantomScene, ABackdropPhotographIsTheRoom) {
  cv::Mat photo(480, 800, CV_8UC3);
  for (int y = 0; y < photo.rows; ++y)
    for (int x = 0; x < photo.cols; ++x)
      photo.at<cv::Vec3b>(y, x) = ((x / 40 + y / 40) % 2) ? cv::Vec3b(200, 180, 160) : cv::Vec3b(40, 60, 90);
  PhantomOptions o = short_run("upright", 1);
  o.backdrop = {photo, photo};
  const PhantomSequence seq = make(o);
  // Scaled to cover 320 × 240 (0.5) and cropped in the middle.
  cv::Mat expected, grey;
  cv::resize(photo, expected, {400, 240}, 0, 0, cv::INTER_AREA);
  cv::cvtColor(expected(cv::Rect(40, 0, 320, 240)), grey, cv::COLOR_BGR2GRAY);
  cv::Mat diff;
  cv::absdiff(seq.background(View::Frontal), grey, diff);
  EXPECT_LT(cv::mean(diff)[0], 1.0);
  PhantomOptions one = o;
  one.backdrop[1] = cv::Mat();
  EXPECT_FALSE(PhantomSequence::create(one));
}

// A frame of the real footage as the room (skipped without the shared data).
TEST(PhantomScene, AFrameOfRealFootageAsTheBackdrop) {
  const std::filesystem::path video = test::source_path("../shared/data/real/caliscope/4_cam_recording/cam_0.mp4");
  if (!std::filesystem::exists(video)) GTEST_SKIP() << video << " is not here";
  cv::VideoCapture capture(video.string(), cv::CAP_FFMPEG);
  cv::Mat frame;
  ASSERT_TRUE(capture.read(frame)) << video;
  test::TempDir dir;
  const auto png = dir / "room.png";
  ASSERT_TRUE(cv::imwrite(png.string(), frame));
  const cv::Mat photo = cv::imread(png.string(), cv::IMREAD_COLOR);  // as `spinewatch phantom --backdrop-*` reads it
  ASSERT_FALSE(photo.empty());
  PhantomOptions o = short_run("upright", 1);
  o.backdrop = {photo, photo};
  o.colour = true;
  const PhantomSequence seq = make(o);
  EXPECT_GT(mean_gradient(seq.background(View::Frontal)), 2 * mean_gradient(make(short_run("upright", 1)).background(View::Frontal)));
}

TEST(PhantomStation, TheDefaultGeometryIsTheDefaultRig) {
  auto rig = station_rig({});
  ASSERT_TRUE(rig) << rig.error().message;
  const CameraRig d = CameraRig::default_rig();
  EXPECT_TRUE(rig->frontal.R.isApprox(d.frontal.R, 1e-12));
  EXPECT_TRUE(rig->lateral.R.isApprox(d.lateral.R, 1e-12));
  EXPECT_LT((rig->frontal.t - d.frontal.t).norm(), 1e-9);
  EXPECT_LT((rig->lateral.t - d.lateral.t).norm(), 1e-9);
}

StationGeometry geometry(std::optional<double> tilt, double roll, double pair, std::optional<double> height) {
  StationGeometry g;
  g.tilt_deg = tilt;
  g.roll_deg = roll;
  g.pair_angle_deg = pair;
  g.height_mm = height;
  return g;
}

Eigen::Vector3d optical_axis(const CameraModel& c) { return c.R.row(2).transpose(); }

TEST(PhantomStation, PairAngleTiltRollAndHeight) {
  for (double angle : {45.0, 60.0, 120.0, 135.0}) {
    auto rig = station_rig(geometry({}, 0, angle, {}));
    ASSERT_TRUE(rig);
    const double between = std::acos(optical_axis(rig->frontal).dot(optical_axis(rig->lateral))) * kDegPerRad;
    EXPECT_NEAR(between, angle, 0.1);
  }
  // Tilted, the cameras look down by the tilt and still at the trunk.
  auto tilted = station_rig(geometry(30, 0, 90, {}));
  ASSERT_TRUE(tilted);
  for (const CameraModel* c : {&tilted->frontal, &tilted->lateral}) {
    EXPECT_NEAR(std::asin(-optical_axis(*c).y()) * kDegPerRad, 30, 1e-9);
    const auto aim = c->project({0, kAimHeightMm, 0});
    ASSERT_TRUE(aim);
    EXPECT_NEAR(aim->x(), 160, 1e-6);
    EXPECT_NEAR(aim->y(), 120, 1e-6);
  }
  // The floor line of the plain room: where the wall meets the floor it
  // rises in the image with the tilt (the renderer draws the rig's view).
  auto boundary_row = [](const PhantomSequence& s) {
    const cv::Mat& bg = s.background(View::Frontal);
    for (int y = bg.rows - 1; y > 0; --y)
      if (cv::mean(bg.row(y - 1))[0] - cv::mean(bg.row(y))[0] > 25) return y;
    return -1;
  };
  PhantomOptions level = short_run("upright", 1), down = level;
  down.station = geometry(20, 0, 90, {});
  const PhantomSequence a = make(level), b = make(down);
  const auto expected = b.camera(View::Frontal).project({-1500, 0, 0});
  ASSERT_TRUE(expected);
  EXPECT_NEAR(boundary_row(a), 120 + 300 * 1100 / 3500.0, 2);
  EXPECT_NEAR(boundary_row(b), expected->y(), 2);
  EXPECT_LT(boundary_row(b), boundary_row(a) - 20);

  // Rolled, the image of a vertical line turns by the roll.
  auto rolled = station_rig(geometry({}, 20, 90, {}));
  ASSERT_TRUE(rolled);
  const auto lo = rolled->frontal.project({0, 800, 0}), hi = rolled->frontal.project({0, 1400, 0});
  const Eigen::Vector2d up = *hi - *lo;
  EXPECT_NEAR(std::atan2(up.x(), -up.y()) * kDegPerRad, -20, 0.1);  // the top of the line leans to image left

  // Raised alone, the cameras tilt to look at the trunk.
  auto high = station_rig(geometry({}, 0, 90, 2000));
  ASSERT_TRUE(high);
  EXPECT_NEAR(high->frontal.centre_in_world().y(), 2000, 1e-9);
  const auto aim = high->lateral.project({0, kAimHeightMm, 0});
  EXPECT_NEAR(aim->y(), 120, 1e-6);
  // Both: where they look must be the trunk.
  EXPECT_TRUE(station_rig(geometry(20, 0, 90, 1800)));
  EXPECT_FALSE(station_rig(geometry(45, 0, 90, 1100)));
  EXPECT_FALSE(station_rig(geometry({}, 0, 150, {})));
  EXPECT_FALSE(station_rig(geometry({}, 30, 90, {})));
}

TEST(PhantomStation, TheHeadingTurnsTheTruthAboutY) {
  PhantomOptions straight = short_run("combined", 5), turned = straight;
  turned.heading_deg = 135;
  const PhantomSequence a = make(straight), b = make(turned);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(135 * kRadPerDeg, Eigen::Vector3d::UnitY()));
  for (int i : {0, 2, 4}) {
    const Posture pa = a.ground_truth(i), pb = b.ground_truth(i);
    ASSERT_TRUE(pa.vertebrae && pb.vertebrae);
    for (std::size_t v = 0; v < pa.vertebrae->size(); ++v) {
      EXPECT_LT((q * (*pa.vertebrae)[v].body_center - (*pb.vertebrae)[v].body_center).norm(), 1e-9);
      EXPECT_LT((q * (*pa.vertebrae)[v].q).angularDistance((*pb.vertebrae)[v].q), 1e-9);
    }
    for (std::size_t j = 0; j < pa.angles.size(); ++j) EXPECT_NEAR(pa.angles[j].flexion, pb.angles[j].flexion, 1e-9);
  }
  // 180°: the back to the frontal camera, so the frontal view sees the same outline mirrored.
  PhantomOptions back = short_run("upright", 1);
  back.heading_deg = 180;
  const cv::Rect e = extent(make(back).render(0), View::Frontal);
  EXPECT_NEAR(e.x + e.width / 2.0, 160, 6);
}

TEST(PhantomCompression, H264ChangesPixelsByABoundedAmount) {
  PhantomOptions o = short_run("flexion", 4);
  o.colour = true;
  const PhantomSequence seq = make(o);
  double error_23 = 0, error_40 = 0;
  for (int crf : {0, 23, 40}) {
    auto stream = H264RoundTrip::create({kImageWidth, kImageHeight}, crf);
    ASSERT_TRUE(stream) << stream.error().message;
    for (int i = 0; i < 4; ++i) {
      const PhantomFrame f = seq.render(i);
      auto coded = stream->pass(f.luma[0], f.chroma[0]);
      ASSERT_TRUE(coded) << coded.error().message;
      ASSERT_EQ(coded->chroma.type(), CV_8UC2);
      const double error = cv::norm(coded->luma, f.luma[0], cv::NORM_L1) / double(f.luma[0].total());
      if (crf == 0) {
        EXPECT_EQ(error, 0);  // lossless luma
      }
      if (crf == 23) error_23 += error / 4;
      if (crf == 40) error_40 += error / 4;
    }
  }
  EXPECT_GT(error_23, 0.3);
  EXPECT_LT(error_23, 4);
  EXPECT_GT(error_40, error_23);
  EXPECT_LT(error_40, 10);
  EXPECT_FALSE(H264RoundTrip::create({kImageWidth, kImageHeight}, 60));
}

TEST(PhantomCompression, ARecordingWrittenThroughH264) {
  test::TempDir dir;
  PhantomOptions o = short_run("upright", 3);
  o.empty_frames = 1;
  const PhantomSequence plain = make(o);
  o.h264_crf = 28;
  const PhantomSequence coded = make(o);
  ASSERT_TRUE(write_recording(plain, dir / "plain"));
  ASSERT_TRUE(write_recording(coded, dir / "coded"));
  const std::string a = test::read_file(dir / "plain" / "frontal.raw"), b = test::read_file(dir / "coded" / "frontal.raw");
  ASSERT_EQ(a.size(), b.size());
  double total = 0;
  for (std::size_t k = 0; k < a.size(); k += 2) total += std::abs(int(std::uint8_t(a[k])) - int(std::uint8_t(b[k])));
  const double mean = total / double(a.size() / 2);
  EXPECT_GT(mean, 0.3);
  EXPECT_LT(mean, 6);
  EXPECT_NE(test::read_file(dir / "coded" / "recording.json").find("h264_crf=28"), std::string::npos);
}

// Both views side by side, noise-free, for docs/phantom.md:
// SPINEWATCH_PHANTOM_IMAGES=docs/images regenerates them; otherwise they
// go to a temporary directory (and are read back).
TEST(PhantomScene, SavesExampleImagesOfTheVariety) {
  test::TempDir tmp;
  const char* env = std::getenv("SPINEWATCH_PHANTOM_IMAGES");
  const std::filesystem::path dir = env ? std::filesystem::path(env) : tmp.path();
  struct Example {
    const char* file;
    PhantomOptions options;
    int frame;
  };
  PhantomOptions typing = short_run("typing", 9), lunge = short_run("lunge", 9), carry = short_run("carry", 9),
                 station = short_run("arms_overhead", 9);
  carry.room = RoomKind::Cluttered;
  station.station = geometry(25, 15, 70, {});
  station.heading_deg = 30;
  for (const Example& e : {Example{"phantom-typing.png", typing, 4}, Example{"phantom-lunge.png", lunge, 4},
                           Example{"phantom-carry-cluttered.png", carry, 2},
                           Example{"phantom-tilt-roll-pair70.png", station, 3}}) {
    const PhantomFrame frame = make(e.options).render(e.frame);
    cv::Mat both;
    cv::hconcat(frame.clean[0], frame.clean[1], both);
    ASSERT_TRUE(cv::imwrite((dir / e.file).string(), both)) << e.file;
    const cv::Mat back = cv::imread((dir / e.file).string(), cv::IMREAD_GRAYSCALE);
    EXPECT_EQ(cv::countNonZero(back != both), 0) << e.file;
  }
}

}  // namespace
}  // namespace spinewatch::phantom

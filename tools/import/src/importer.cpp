#include "spinewatch/import/importer.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>  // the flags; the codecs are the media module's
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/import/crop.hpp"
#include "spinewatch/import/video_clip.hpp"
#include "spinewatch/import/station_rig.hpp"
#include "spinewatch/import/yuyv.hpp"
#include "spinewatch/media/media_files.hpp"

namespace spinewatch::import {
namespace {

namespace fs = std::filesystem;

constexpr const char* kViewNames[2] = {"frontal", "lateral"};

// One camera's side of the import.
struct Side {
  VideoClip clip;
  int frames = 0;
  MotionMap motion;
  CropRect crop;
};

Status check_size(const CameraModel& cam, const VideoClip& clip, const std::string& camera_id,
                  const std::filesystem::path& calibration) {
  if (cam.image_width == 0) return Ok{};
  if (cam.image_width != clip.width() || cam.image_height != clip.height())
    return Error{fmt::format("{}: {}x{}, but camera {} of {} was calibrated at {}x{}: a calibration holds only at "
                             "the resolution it was made at; give the video recorded at that size, or the "
                             "calibration made for this one",
                             clip.path().string(), clip.width(), clip.height(), camera_id, calibration.string(),
                             cam.image_width, cam.image_height)};
  return Ok{};
}

// The crop given for a camera, or the one holding the clip's motion.
Result<CropRect> choose_crop(const std::string& given, Side& side, const char* view) {
  const int w = side.clip.width(), h = side.clip.height();
  if (!given.empty()) {
    auto crop = parse_crop(given, w, h);
    if (!crop) return crop.error();
    spdlog::info("{}: crop {} (given)", view, crop->describe());
    return crop;
  }
  auto box = motion_box(side.motion);
  // At least a third of the frame's height: a person filling less than
  // that at 320×240 would be too few pixels, and a small box is more often
  // a hand than the body.
  const int min_width = std::min(w, h * 4 / 3) / 2;
  if (!box) {
    CropRect crop = crop_around(0, 0, w, h, w, h, 0.0, w);
    spdlog::info("{}: crop {}: nothing moved in the clip, the largest 4:3 centre (give --crop-{} X,Y,W,H)", view,
                 crop.describe(), view);
    return crop;
  }
  CropRect crop = crop_around(box->x, box->y, box->width, box->height, w, h, 0.1, min_width);
  spdlog::info("{}: crop {}: holds where the clip moved ({}x{}+{}+{}, 2 % trimmed each side) with a 10 % margin "
               "(give --crop-{} X,Y,W,H to choose)",
               view, crop.describe(), box->width, box->height, box->x, box->y, view);
  return crop;
}

// The pairs to import: frontal frames [first_f, first_f + count) with
// lateral frames from first_f + offset.
struct Pairing {
  int first[2] = {0, 0};
  int count = 0;
};

Result<Pairing> pair_frames(const ImportOptions& o, const Side sides[2]) {
  Pairing p;
  p.first[0] = std::max(0, -o.offset);
  p.first[1] = p.first[0] + o.offset;
  const int left[2] = {sides[0].frames - p.first[0], sides[1].frames - p.first[1]};
  const std::string lengths =
      fmt::format("{} has {} frames, {} has {}", o.frontal_video.string(), sides[0].frames,
                  o.lateral_video.string(), sides[1].frames);
  if (left[0] <= 0 || left[1] <= 0)
    return Error{fmt::format("--offset {} leaves no frame to pair: {}", o.offset, lengths)};
  if (o.frames) {
    if (*o.frames < 1 || *o.frames > std::min(left[0], left[1]))
      return Error{fmt::format("--frames {}: with --offset {} at most {} pairs ({})", *o.frames, o.offset,
                               std::min(left[0], left[1]), lengths)};
    p.count = *o.frames;
  } else if (left[0] != left[1] && o.offset == 0) {
    return Error{fmt::format("the videos differ in length: {}. Frame i of one pairs with frame i of the other: "
                             "give --offset N if the lateral video started N frames later (negative: earlier), "
                             "or --frames N to import the first N pairs",
                             lengths)};
  } else {
    p.count = std::min(left[0], left[1]);
    if (left[0] != left[1])
      spdlog::info("with --offset {}: {} pairs; the longer clip's last {} frames are left out", o.offset, p.count,
                   std::abs(left[0] - left[1]));
  }
  return p;
}

SceneImage scene_of(const cv::Mat& bgr_out) {
  SceneImage image;
  image.width = bgr_out.cols;
  image.height = bgr_out.rows;
  image.step = 2;
  bgr_to_yuyv(bgr_out, image.pixels);
  return image;
}

cv::Mat crop_and_scale(const cv::Mat& bgr, const CropRect& c) {
  cv::Mat out;
  cv::resize(bgr(cv::Rect(c.x, c.y, c.width, c.height)), out, cv::Size(kOutWidth, kOutHeight), 0, 0,
             c.width == kOutWidth ? cv::INTER_NEAREST : cv::INTER_AREA);
  return out;
}

Result<SceneImage> background_from_file(const std::filesystem::path& path, const Side& side) {
  cv::Mat image;
  try {
    auto read = media::read_image(path, cv::IMREAD_COLOR);
    if (!read) return read.error();
    image = std::move(*read);
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: could not be read ({})", path.string(), e.err)};
  }
  if (image.empty()) return Error{fmt::format("{}: not an image OpenCV can read", path.string())};
  if (image.cols != side.clip.width() || image.rows != side.clip.height())
    return Error{fmt::format("{}: {}x{}, but its video is {}x{}: the background must be the camera's full frame",
                             path.string(), image.cols, image.rows, side.clip.width(), side.clip.height())};
  return scene_of(crop_and_scale(image, side.crop));
}

// The per-pixel, per-channel median of the frames (a scene the person
// moves through shows its background at most instants).
cv::Mat median_of(const std::vector<cv::Mat>& frames) {
  cv::Mat out(kOutHeight, kOutWidth, CV_8UC3);
  std::vector<std::uint8_t> values(frames.size());
  const std::size_t mid = frames.size() / 2;
  for (int y = 0; y < kOutHeight; ++y)
    for (int x = 0; x < kOutWidth * 3; ++x) {
      for (std::size_t k = 0; k < frames.size(); ++k) values[k] = frames[k].ptr<std::uint8_t>(y)[x];
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
      out.ptr<std::uint8_t>(y)[x] = values[mid];
    }
  return out;
}

nlohmann::json rows(const Eigen::Matrix3d& m) {
  nlohmann::json out = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) out.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return out;
}

// import.json: where the recording came from and the station's frame in
// the calibration's, so that postures can be taken back into it
// (X_file = axesᵀ · X_station + origin) and compared across camera pairs.
Status write_provenance(const ImportOptions& o, const StationRig& station, const Side sides[2]) {
  nlohmann::json j;
  j["calibration"] = {{"file", o.calibration.string()}, {"format", station.format}};
  j["cameras"] = {{"frontal", station.ids[0]}, {"lateral", station.ids[1]}};
  j["videos"] = {{"frontal", o.frontal_video.string()}, {"lateral", o.lateral_video.string()}};
  j["offset"] = o.offset;
  for (int v = 0; v < 2; ++v) {
    const CropRect& c = sides[v].crop;
    j["crop"][kViewNames[v]] = {c.x, c.y, c.width, c.height};
  }
  j["world_frame"] = {{"axes", rows(station.frame.axes)},
                      {"origin_mm", {station.frame.origin.x(), station.frame.origin.y(), station.frame.origin.z()}},
                      {"report", station.frame.report}};
  const fs::path path = o.out / "import.json";
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) return Error{fmt::format("{}: cannot be written", path.string())};
  return Ok{};
}

}  // namespace

Result<ImportSummary> import_recording(const ImportOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (o.median_background && (!o.background_frontal.empty() || !o.background_lateral.empty()))
    return Error{"--median-background and --background-frontal/--background-lateral: choose one"};
  if (o.background_frontal.empty() != o.background_lateral.empty())
    return Error{"--background-frontal and --background-lateral come together (one image per camera)"};

  auto station = station_rig_from(RigChoice{o.calibration, o.frontal_camera, o.lateral_camera, o.up,
                                            o.camera_height_mm});
  if (!station) return station.error();
  for (const std::string& line : station->report) spdlog::info("{}", line);
  const std::string* ids = station->ids;

  auto frontal = VideoClip::open(o.frontal_video);
  if (!frontal) return frontal.error();
  auto lateral = VideoClip::open(o.lateral_video);
  if (!lateral) return lateral.error();
  Side sides[2] = {Side{std::move(*frontal), 0, {}, {}}, Side{std::move(*lateral), 0, {}, {}}};
  const CameraModel* file_cams[2] = {&station->rig.frontal, &station->rig.lateral};
  for (int v = 0; v < 2; ++v)
    if (auto s = check_size(*file_cams[v], sides[v].clip, ids[v], o.calibration); !s) return s.error();

  // Pass 1: lengths and motion.
  for (int v = 0; v < 2; ++v) {
    const bool want_motion = (v == 0 ? o.crop_frontal : o.crop_lateral).empty();
    auto n = sides[v].clip.scan(want_motion ? &sides[v].motion : nullptr);
    if (!n) return n.error();
    if (*n == 0) return Error{fmt::format("{}: no frames", sides[v].clip.path().string())};
    sides[v].frames = *n;
  }
  auto pairing = pair_frames(o, sides);
  if (!pairing) return pairing.error();
  for (int v = 0; v < 2; ++v) {
    auto crop = choose_crop(v == 0 ? o.crop_frontal : o.crop_lateral, sides[v], kViewNames[v]);
    if (!crop) return crop.error();
    sides[v].crop = *crop;
  }

  // The calibration of the cropped, scaled images.
  const CameraRig rig{crop_camera(station->rig.frontal, sides[0].crop), crop_camera(station->rig.lateral, sides[1].crop)};

  const double fps = sides[0].clip.fps() > 0 ? sides[0].clip.fps() : 30.0;
  auto writer = RecordingWriter::create(o.out, FrameFormat::packed(PixelFormat::YUYV, kOutWidth, kOutHeight), fps);
  if (!writer) return writer.error();
  if (auto s = save_calibration(o.out / "calibration.yaml", rig); !s) return s.error();

  // Pass 2: the frames.
  for (int v = 0; v < 2; ++v)
    if (auto s = sides[v].clip.skip(pairing->first[v]); !s) return s.error();
  std::vector<cv::Mat> kept[2];
  cv::Mat bgr;
  std::vector<std::uint8_t> yuyv;
  for (int i = 0; i < pairing->count; ++i)
    for (int v = 0; v < 2; ++v) {
      if (!sides[v].clip.next(bgr))
        return Error{fmt::format("{}: frame {} could not be decoded the second time", sides[v].clip.path().string(),
                                 pairing->first[v] + i)};
      cv::Mat out = crop_and_scale(bgr, sides[v].crop);
      bgr_to_yuyv(out, yuyv);
      const FrameInfo info{static_cast<std::uint64_t>(i), static_cast<std::int64_t>(i * 1e9 / fps)};
      Frame frame_out = Frame::copy_of(FrameFormat::packed(PixelFormat::YUYV, kOutWidth, kOutHeight), info, yuyv);
      if (auto s = writer->write(static_cast<View>(v), frame_out); !s) return s.error();
      if (o.median_background) kept[v].push_back(out);
    }

  if (!o.background_frontal.empty()) {
    BackgroundImages images;
    auto f = background_from_file(o.background_frontal, sides[0]);
    if (!f) return f.error();
    auto l = background_from_file(o.background_lateral, sides[1]);
    if (!l) return l.error();
    images.frontal = std::move(*f);
    images.lateral = std::move(*l);
    if (auto s = write_background_images(o.out, images); !s) return s.error();
    spdlog::info("backgrounds: {} and {}, cropped and scaled as the frames", o.background_frontal.string(),
                 o.background_lateral.string());
  } else if (o.median_background) {
    BackgroundImages images{scene_of(median_of(kept[0])), scene_of(median_of(kept[1]))};
    if (auto s = write_background_images(o.out, images); !s) return s.error();
    spdlog::info("backgrounds: the per-pixel median of the {} imported frames of each camera (the person shows "
                 "in it where he stayed still)",
                 pairing->count);
  }

  const std::string notes = fmt::format(
      "imported by spinewatch import from {} (camera {}, crop {}) and {} (camera {}, crop {}), calibration {} ({}), "
      "offset {}",
      o.frontal_video.string(), ids[0], sides[0].crop.describe(), o.lateral_video.string(), ids[1],
      sides[1].crop.describe(), o.calibration.string(), station->format, o.offset);
  if (auto s = writer->finish(nullptr, notes); !s) return s.error();
  if (auto s = write_provenance(o, *station, sides); !s) return s.error();
  ImportSummary summary;
  summary.pairs = pairing->count;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace spinewatch::import

// spinewatch-landmarks: measures MediaPipe's BlazePose landmark model run by
// Arm NN beside the fit (docs/cvsm.md, "A learned landmark model beside the
// fit"). Built only where Arm NN and its TfLite parser are installed.
//
//   probe MODEL...   does Arm NN parse and optimise it; its tensors
//   frame            one video frame as a PNG (to choose a crop by hand)
//   run              the model on a square crop of video frames: overlays,
//                    masks at the frame's size, landmarks, time per inference;
//                    with --masked-video, the video again with everything but
//                    the mask painted one colour, and --background-out that
//                    colour as the empty scene: what `spinewatch import` takes
//                    to fit the mask as the silhouette (docs/cvsm.md)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "spinewatch/landmarks/crop_input.hpp"
#include "spinewatch/landmarks/pose_landmarker.hpp"

namespace lm = spinewatch::landmarks;

namespace {

std::string shape_text(const std::vector<unsigned>& shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? "," : "") + std::to_string(shape[i]);
  return s + "]";
}

int probe(const std::vector<std::string>& models, const std::vector<std::string>& backends) {
  int failures = 0;
  for (const auto& model : models) {
    std::printf("%s\n", model.c_str());
    try {
      const lm::PoseLandmarker landmarker(model, backends);
      const auto& d = landmarker.description();
      std::printf("  folded %zu float16 DEQUANTIZE operators, %zu operators left, %zu resizes given back half-pixel "
                  "sampling; optimised for", d.dequantize_folded, d.operators, d.half_pixel_resizes);
      for (const auto& b : backends) std::printf(" %s", b.c_str());
      std::printf(" (registered:");
      for (const auto& b : d.backends_available) std::printf(" %s", b.c_str());
      std::printf(")\n");
      for (const auto& t : d.inputs) std::printf("  input  %s %s %s\n", t.name.c_str(), shape_text(t.shape).c_str(), t.type.c_str());
      for (const auto& t : d.outputs) std::printf("  output %s %s %s\n", t.name.c_str(), shape_text(t.shape).c_str(), t.type.c_str());
    } catch (const std::exception& e) {
      std::printf("  FAILED: %s\n", e.what());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}

cv::Mat read_frame(cv::VideoCapture& video, int index) {
  video.set(cv::CAP_PROP_POS_FRAMES, index);
  cv::Mat frame;
  if (!video.read(frame)) throw std::runtime_error("cannot read frame " + std::to_string(index));
  return frame;
}

// BlazePose's body landmarks joined as a stick figure (0 nose … 32 right
// foot index; MediaPipe's documented landmark order).
constexpr std::pair<int, int> kBones[] = {{11, 12}, {11, 13}, {13, 15}, {12, 14}, {14, 16}, {11, 23}, {12, 24},
                                          {23, 24}, {23, 25}, {25, 27}, {24, 26}, {26, 28}, {0, 11}, {0, 12}};

void draw_overlay(cv::Mat& image, const lm::PoseOutput& out, const lm::SquareCrop& crop, const cv::Mat& mask) {
  cv::Mat tint(image.size(), image.type(), cv::Scalar(0, 180, 0));
  cv::Mat blended;
  cv::addWeighted(image, 0.6, tint, 0.4, 0, blended);
  blended.copyTo(image, mask);
  cv::rectangle(image, cv::Rect(crop.x, crop.y, crop.side, crop.side), cv::Scalar(255, 255, 0), 2);
  const auto at = [&](int k) { return crop.to_frame(out.landmarks[k].x, out.landmarks[k].y, lm::kInputSide); };
  for (const auto& [a, b] : kBones) cv::line(image, at(a), at(b), cv::Scalar(0, 0, 255), 2);
  for (int k = 0; k < lm::kBodyLandmarks; ++k) {
    const bool visible = out.landmarks[k].visibility > 0;  // logit > 0 ⇔ p > 0.5
    cv::circle(image, at(k), 5, visible ? cv::Scalar(0, 255, 255) : cv::Scalar(255, 0, 255), -1);
  }
}

// What is not person in a masked video: saturated green, far in colour from
// skin, dark clothing and the room, so that the station's colour test
// (docs/tuning.md, "Silhouettes") finds exactly the mask.
const cv::Scalar kMaskedBackground(0, 255, 0);

struct RunOptions {
  std::string model, video, out_dir, masked_video, background_out;
  bool all_frames = false, overlays = true;
  std::vector<std::string> backends{"CpuRef"};
  std::vector<int> crop;  // x, y, side
  int first = 0, count = 1, step = 1;
  float threshold = 0.5f;
  lm::InputRange range = lm::InputRange::kUnit;
};

int run(const RunOptions& o) {
  const lm::SquareCrop crop{o.crop.at(0), o.crop.at(1), o.crop.at(2)};
  lm::PoseLandmarker landmarker(o.model, o.backends);
  cv::VideoCapture video(o.video);
  if (!video.isOpened()) throw std::runtime_error("cannot open " + o.video);
  std::filesystem::create_directories(o.out_dir);
  std::ofstream ndjson(o.out_dir + "/landmarks.ndjson");
  const int frames = static_cast<int>(video.get(cv::CAP_PROP_FRAME_COUNT));
  const int count = o.all_frames ? (frames - o.first + o.step - 1) / o.step : o.count;
  cv::VideoWriter masked;
  if (!o.masked_video.empty()) {
    const cv::Size size(static_cast<int>(video.get(cv::CAP_PROP_FRAME_WIDTH)),
                        static_cast<int>(video.get(cv::CAP_PROP_FRAME_HEIGHT)));
    // FFV1: lossless, so the mask's edge is not smeared by compression.
    if (!masked.open(o.masked_video, cv::VideoWriter::fourcc('F', 'F', 'V', '1'), video.get(cv::CAP_PROP_FPS), size)) {
      throw std::runtime_error("cannot write " + o.masked_video);
    }
    if (!o.background_out.empty()) cv::imwrite(o.background_out, cv::Mat(size, CV_8UC3, kMaskedBackground));
  }
  std::vector<double> ms;
  for (int i = 0; i < count; ++i) {
    const int index = o.first + i * o.step;
    cv::Mat frame = read_frame(video, index);
    const auto input = lm::crop_to_input(frame, crop, lm::kInputSide, o.range);
    const auto t0 = std::chrono::steady_clock::now();
    const lm::PoseOutput out = landmarker.infer(input);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    const cv::Mat mask = lm::mask_to_frame(out.mask, lm::kInputSide, crop, frame.size(), o.threshold);
    char name[64];
    std::snprintf(name, sizeof name, "/mask_%04d.png", index);
    if (masked.isOpened()) {
      cv::Mat painted(frame.size(), frame.type(), kMaskedBackground);
      frame.copyTo(painted, mask);
      masked.write(painted);
    }
    if (o.overlays) {
      cv::imwrite(o.out_dir + name, mask);
      draw_overlay(frame, out, crop, mask);
      std::snprintf(name, sizeof name, "/overlay_%04d.png", index);
      cv::imwrite(o.out_dir + name, frame);
    }
    ndjson << "{\"frame\":" << index << ",\"presence\":" << out.presence_score << ",\"ms\":" << ms.back()
           << ",\"mask_pixels\":" << cv::countNonZero(mask) << ",\"landmarks\":[";
    for (int k = 0; k < lm::kLandmarks; ++k) {
      const auto p = crop.to_frame(out.landmarks[k].x, out.landmarks[k].y, lm::kInputSide);
      ndjson << (k ? "," : "") << "[" << p.x << "," << p.y << "," << out.landmarks[k].visibility << "]";
    }
    ndjson << "]}\n";
    std::printf("frame %d: presence %.3f, mask %d px, %.0f ms\n", index, out.presence_score, cv::countNonZero(mask),
                ms.back());
  }
  std::sort(ms.begin(), ms.end());
  std::printf("inference: median %.1f ms, min %.1f, max %.1f over %zu\n", ms[ms.size() / 2], ms.front(), ms.back(),
              ms.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"BlazePose landmarks by Arm NN beside the fit (docs/cvsm.md)"};
  app.require_subcommand(1);
  std::vector<std::string> models, backends{"CpuRef"};
  auto* probe_cmd = app.add_subcommand("probe", "parse and optimise the models; print their tensors");
  probe_cmd->add_option("models", models, ".tflite files")->required()->check(CLI::ExistingFile);
  probe_cmd->add_option("--backend", backends, "Arm NN backends in preference order");

  std::string video, out;
  int index = 0;
  auto* frame_cmd = app.add_subcommand("frame", "write one video frame as a PNG");
  frame_cmd->add_option("--video", video)->required()->check(CLI::ExistingFile);
  frame_cmd->add_option("--index", index);
  frame_cmd->add_option("--out", out)->required();

  RunOptions ro;
  auto* run_cmd = app.add_subcommand("run", "the model on a square crop of video frames");
  run_cmd->add_option("--model", ro.model)->required()->check(CLI::ExistingFile);
  run_cmd->add_option("--video", ro.video)->required()->check(CLI::ExistingFile);
  run_cmd->add_option("--crop", ro.crop, "x,y,side in frame pixels")->required()->expected(3)->delimiter(',');
  run_cmd->add_option("--first", ro.first);
  run_cmd->add_option("--count", ro.count)->check(CLI::PositiveNumber);
  run_cmd->add_option("--step", ro.step)->check(CLI::PositiveNumber);
  run_cmd->add_option("--threshold", ro.threshold, "mask probability threshold")->check(CLI::Range(0.01, 0.99));
  const std::map<std::string, lm::InputRange> ranges{{"unit", lm::InputRange::kUnit}, {"signed", lm::InputRange::kSigned}};
  run_cmd->add_option("--input-range", ro.range, "unit: [0, 1] (MediaPipe's); signed: [-1, 1]")
      ->transform(CLI::CheckedTransformer(ranges, CLI::ignore_case));
  run_cmd->add_flag("--all-frames", ro.all_frames, "from --first to the video's end, every --step");
  run_cmd->add_option("--masked-video", ro.masked_video, "write the video with all but the mask painted green (FFV1)");
  run_cmd->add_option("--background-out", ro.background_out, "with --masked-video: that green as a background PNG");
  run_cmd->add_flag("!--no-overlays", ro.overlays, "write no overlay or mask PNGs");
  run_cmd->add_option("--backend", ro.backends, "Arm NN backends in preference order");
  run_cmd->add_option("--out-dir", ro.out_dir)->required();
  CLI11_PARSE(app, argc, argv);
  try {
    if (*probe_cmd) return probe(models, backends);
    if (*frame_cmd) {
      cv::VideoCapture v(video);
      return cv::imwrite(out, read_frame(v, index)) ? 0 : 1;
    }
    return run(ro);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spinewatch-landmarks: %s\n", e.what());
    return 1;
  }
}

#pragma once
// MediaPipe's BlazePose landmark model (pose_landmark_{lite,full,heavy}.tflite
// from the npm package @mediapipe/pose) run by Arm NN through its TfLite
// parser, on the backends asked for (CpuRef everywhere; CpuAcc on ARM).
//
// The model takes a 256×256 RGB crop around one person and gives, in that
// crop's pixels, 39 landmarks (BlazePose's 33 and 6 auxiliary ones), a
// person-presence score, a 256×256 segmentation mask, a 64×64×39 heatmap
// and the landmarks in metres about the hips.
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace spinewatch::landmarks {

inline constexpr int kInputSide = 256;
inline constexpr int kLandmarks = 39;  // 33 body landmarks, then 6 auxiliary
inline constexpr int kBodyLandmarks = 33;

struct Landmark {
  float x = 0, y = 0, z = 0;  // crop pixels (z: depth, same scale as x)
  float visibility = 0;       // logit
  float presence = 0;         // logit
};

struct PoseOutput {
  std::array<Landmark, kLandmarks> landmarks{};
  float presence_score = 0;   // the model's person-presence output, as it gives it
  std::vector<float> mask;    // kInputSide², row-major, logits (sigmoid → probability)
};

struct TensorDescription {
  std::string name;
  std::vector<unsigned> shape;
  std::string type;
};

struct ModelDescription {
  std::size_t dequantize_folded = 0;
  std::size_t operators = 0;
  std::size_t half_pixel_resizes = 0;  // Resize layers given back their half-pixel sampling
  std::vector<TensorDescription> inputs, outputs;
  std::vector<std::string> backends_available;  // registered with Arm NN on this machine
};

class PoseLandmarker {
 public:
  // Loads, folds (tflite_fold.hpp), parses, restores the resizes' half-pixel
  // sampling (tflite_resize.hpp) and optimises the model for
  // `backends` in preference order; throws std::runtime_error with Arm NN's
  // message when any step fails.
  PoseLandmarker(const std::string& model_path, const std::vector<std::string>& backends);
  ~PoseLandmarker();
  PoseLandmarker(const PoseLandmarker&) = delete;
  PoseLandmarker& operator=(const PoseLandmarker&) = delete;

  const ModelDescription& description() const;

  // `rgb`: kInputSide² × 3 floats, row-major, each channel in [0, 1].
  PoseOutput infer(const std::vector<float>& rgb);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch::landmarks

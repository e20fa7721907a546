#include "spinewatch/landmarks/pose_landmarker.hpp"

#include <armnn/ArmNN.hpp>
#include <armnnTfLiteParser/ITfLiteParser.hpp>

#include <algorithm>
#include <fstream>
#include <set>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "network_copy.hpp"
#include "spinewatch/landmarks/tflite_fold.hpp"
#include "spinewatch/landmarks/tflite_resize.hpp"

namespace spinewatch::landmarks {
namespace {

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TensorDescription describe(const std::string& name, const armnn::TensorInfo& info) {
  TensorDescription d{name, {}, armnn::GetDataTypeName(info.GetDataType())};
  for (unsigned i = 0; i < info.GetNumDimensions(); ++i) d.shape.push_back(info.GetShape()[i]);
  return d;
}

// Which of the model's outputs is which, told apart by their shapes
// (their names, Identity…Identity_4, say nothing).
enum class Output { kLandmarks, kPresence, kMask, kHeatmap, kWorldLandmarks, kUnknown };

Output classify(const armnn::TensorInfo& info) {
  const unsigned n = info.GetNumElements();
  if (n == kLandmarks * 5) return Output::kLandmarks;
  if (n == 1) return Output::kPresence;
  if (n == kInputSide * kInputSide) return Output::kMask;
  if (n == kLandmarks * 3) return Output::kWorldLandmarks;
  if (info.GetNumDimensions() == 4 && info.GetShape()[3] == kLandmarks) return Output::kHeatmap;
  return Output::kUnknown;
}

}  // namespace

struct PoseLandmarker::Impl {
  armnn::IRuntimePtr runtime{nullptr, &armnn::IRuntime::Destroy};
  armnn::NetworkId network = 0;
  armnnTfLiteParser::BindingPointInfo input;
  std::vector<std::pair<armnnTfLiteParser::BindingPointInfo, Output>> outputs;
  std::vector<std::vector<float>> output_data;
  ModelDescription description;
};

PoseLandmarker::PoseLandmarker(const std::string& model_path, const std::vector<std::string>& backends)
    : impl_(std::make_unique<Impl>()) {
  auto bytes = read_file(model_path);
  const FoldReport fold = fold_float16_weights(bytes);
  impl_->description.dequantize_folded = fold.dequantize_folded;
  impl_->description.operators = fold.operators_left;

  auto parser = armnnTfLiteParser::ITfLiteParser::Create();
  const armnn::INetworkPtr parsed = parser->CreateNetworkFromBinary(bytes);  // throws armnn::Exception
  const std::set<std::size_t> half_pixel = half_pixel_resizes(bytes);
  impl_->description.half_pixel_resizes = half_pixel.size();
  const armnn::INetworkPtr network = copy_with_half_pixel_resizes(*parsed, half_pixel);
  const auto input_names = parser->GetSubgraphInputTensorNames(0);
  if (input_names.size() != 1) throw std::runtime_error(model_path + ": expected one input");
  impl_->input = parser->GetNetworkInputBindingInfo(0, input_names[0]);
  impl_->description.inputs.push_back(describe(input_names[0], impl_->input.second));
  for (const auto& name : parser->GetSubgraphOutputTensorNames(0)) {
    const auto binding = parser->GetNetworkOutputBindingInfo(0, name);
    impl_->outputs.emplace_back(binding, classify(binding.second));
    impl_->output_data.emplace_back(binding.second.GetNumElements());
    impl_->description.outputs.push_back(describe(name, binding.second));
  }

  impl_->runtime = armnn::IRuntime::Create(armnn::IRuntime::CreationOptions());
  for (const auto& id : impl_->runtime->GetDeviceSpec().GetSupportedBackends()) {
    impl_->description.backends_available.push_back(id.Get());
  }
  std::vector<armnn::BackendId> preferred(backends.begin(), backends.end());
  std::vector<std::string> messages;
  armnn::IOptimizedNetworkPtr optimised =
      armnn::Optimize(*network, preferred, impl_->runtime->GetDeviceSpec(), armnn::OptimizerOptions(),
                      armnn::Optional<std::vector<std::string>&>(messages));
  if (!optimised) {
    std::ostringstream why;
    why << model_path << ": Arm NN could not optimise it for the backends asked for";
    for (const auto& m : messages) why << "; " << m;
    throw std::runtime_error(why.str());
  }
  std::string error;
  if (impl_->runtime->LoadNetwork(impl_->network, std::move(optimised), error, armnn::INetworkProperties()) !=
      armnn::Status::Success) {
    throw std::runtime_error(model_path + ": LoadNetwork failed: " + error);
  }
}

PoseLandmarker::~PoseLandmarker() = default;

const ModelDescription& PoseLandmarker::description() const { return impl_->description; }

PoseOutput PoseLandmarker::infer(const std::vector<float>& rgb) {
  if (rgb.size() != impl_->input.second.GetNumElements()) {
    throw std::invalid_argument("PoseLandmarker::infer: input has the wrong size");
  }
  const armnn::InputTensors inputs{
      {impl_->input.first, armnn::ConstTensor(impl_->runtime->GetInputTensorInfo(impl_->network, impl_->input.first),
                                              rgb.data())}};
  armnn::OutputTensors outputs;
  for (std::size_t i = 0; i < impl_->outputs.size(); ++i) {
    const auto id = impl_->outputs[i].first.first;
    outputs.emplace_back(id, armnn::Tensor(impl_->runtime->GetOutputTensorInfo(impl_->network, id),
                                           impl_->output_data[i].data()));
  }
  if (impl_->runtime->EnqueueWorkload(impl_->network, inputs, outputs) != armnn::Status::Success) {
    throw std::runtime_error("PoseLandmarker::infer: EnqueueWorkload failed");
  }
  PoseOutput result;
  for (std::size_t i = 0; i < impl_->outputs.size(); ++i) {
    const auto& data = impl_->output_data[i];
    switch (impl_->outputs[i].second) {
      case Output::kLandmarks:
        for (int k = 0; k < kLandmarks; ++k) {
          result.landmarks[k] = {data[5 * k], data[5 * k + 1], data[5 * k + 2], data[5 * k + 3], data[5 * k + 4]};
        }
        break;
      case Output::kPresence: result.presence_score = data[0]; break;
      case Output::kMask: result.mask = data; break;
      default: break;
    }
  }
  return result;
}

}  // namespace spinewatch::landmarks

#include "network_copy.hpp"

#include <armnn/LayerVisitorBase.hpp>

#include <map>
#include <stdexcept>
#include <string>

namespace spinewatch::landmarks {
namespace {

// The TFLite operator index in a layer name the parser gave
// ("Resize:BILINEAR:0:71": subgraph 0, operator 71).
std::size_t operator_index(const char* name) {
  const std::string s = name != nullptr ? name : "";
  const auto colon = s.rfind(':');
  if (colon == std::string::npos) throw std::runtime_error("layer \"" + s + "\" names no operator");
  return std::stoul(s.substr(colon + 1));
}

// Visits the parsed network in its (topological) order and adds each layer
// to the copy, connected as the original.
class Copier : public armnn::LayerVisitorBase<armnn::VisitorThrowingPolicy> {
 public:
  explicit Copier(const std::set<std::size_t>& half_pixel) : half_pixel_(half_pixel) {}

  armnn::INetworkPtr take() { return std::move(copy_); }

  void VisitInputLayer(const armnn::IConnectableLayer* l, armnn::LayerBindingId id, const char* name) override {
    add(l, copy_->AddInputLayer(id, name));
  }
  void VisitOutputLayer(const armnn::IConnectableLayer* l, armnn::LayerBindingId id, const char* name) override {
    add(l, copy_->AddOutputLayer(id, name));
  }
  void VisitConvolution2dLayer(const armnn::IConnectableLayer* l, const armnn::Convolution2dDescriptor& d,
                               const armnn::ConstTensor& weights, const armnn::Optional<armnn::ConstTensor>& biases,
                               const char* name) override {
    add(l, copy_->AddConvolution2dLayer(d, weights, biases, name));
  }
  void VisitDepthwiseConvolution2dLayer(const armnn::IConnectableLayer* l,
                                        const armnn::DepthwiseConvolution2dDescriptor& d,
                                        const armnn::ConstTensor& weights,
                                        const armnn::Optional<armnn::ConstTensor>& biases, const char* name) override {
    add(l, copy_->AddDepthwiseConvolution2dLayer(d, weights, biases, name));
  }
  void VisitActivationLayer(const armnn::IConnectableLayer* l, const armnn::ActivationDescriptor& d,
                            const char* name) override {
    add(l, copy_->AddActivationLayer(d, name));
  }
  void VisitAdditionLayer(const armnn::IConnectableLayer* l, const char* name) override {
    add(l, copy_->AddAdditionLayer(name));
  }
  void VisitPooling2dLayer(const armnn::IConnectableLayer* l, const armnn::Pooling2dDescriptor& d,
                           const char* name) override {
    add(l, copy_->AddPooling2dLayer(d, name));
  }
  void VisitReshapeLayer(const armnn::IConnectableLayer* l, const armnn::ReshapeDescriptor& d,
                         const char* name) override {
    add(l, copy_->AddReshapeLayer(d, name));
  }
  void VisitPadLayer(const armnn::IConnectableLayer* l, const armnn::PadDescriptor& d, const char* name) override {
    add(l, copy_->AddPadLayer(d, name));
  }
  void VisitConstantLayer(const armnn::IConnectableLayer* l, const armnn::ConstTensor& t, const char* name) override {
    add(l, copy_->AddConstantLayer(t, name));
  }
  void VisitResizeLayer(const armnn::IConnectableLayer* l, const armnn::ResizeDescriptor& d, const char* name) override {
    armnn::ResizeDescriptor fixed = d;
    if (half_pixel_.count(operator_index(name)) != 0) fixed.m_HalfPixelCenters = true;
    add(l, copy_->AddResizeLayer(fixed, name));
  }

 private:
  void add(const armnn::IConnectableLayer* original, armnn::IConnectableLayer* copy) {
    for (unsigned i = 0; i < original->GetNumInputSlots(); ++i) {
      const armnn::IOutputSlot* source = original->GetInputSlot(i).GetConnection();
      if (source == nullptr) continue;
      const auto it = copies_.find(source->GetOwningLayerGuid());
      if (it == copies_.end()) throw std::runtime_error("network copy: a layer's input was not copied before it");
      it->second->GetOutputSlot(source->CalculateIndexOnOwner()).Connect(copy->GetInputSlot(i));
    }
    for (unsigned k = 0; k < original->GetNumOutputSlots(); ++k) {
      copy->GetOutputSlot(k).SetTensorInfo(original->GetOutputSlot(k).GetTensorInfo());
    }
    copies_[original->GetGuid()] = copy;
  }

  const std::set<std::size_t>& half_pixel_;
  armnn::INetworkPtr copy_ = armnn::INetwork::Create();
  std::map<armnn::LayerGuid, armnn::IConnectableLayer*> copies_;
};

}  // namespace

armnn::INetworkPtr copy_with_half_pixel_resizes(const armnn::INetwork& parsed,
                                                const std::set<std::size_t>& half_pixel_operators) {
  Copier copier(half_pixel_operators);
  parsed.Accept(copier);
  return copier.take();
}

}  // namespace spinewatch::landmarks

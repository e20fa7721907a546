#pragma once
// A copy of an Arm NN network, layer by layer, with the half-pixel sampling
// that Arm NN 20.08's TfLite parser dropped put back into the Resize layers
// whose TFLite operators asked for it (tflite_resize.hpp). Arm NN's
// reference backend samples half-pixel centres correctly; only the parser
// loses the option. Throws on a layer type the copy does not know (the
// BlazePose landmark models use only the ones it knows).
#include <armnn/ArmNN.hpp>

#include <cstddef>
#include <set>

namespace spinewatch::landmarks {

armnn::INetworkPtr copy_with_half_pixel_resizes(const armnn::INetwork& parsed,
                                                const std::set<std::size_t>& half_pixel_operators);

}  // namespace spinewatch::landmarks

#pragma once
// Which RESIZE_BILINEAR operators of a TFLite model sample at half-pixel
// centres (ResizeBilinearOptions.half_pixel_centers). Arm NN 20.08's TfLite
// parser drops that option (its ResizeDescriptor has the field, its parser
// leaves it false), which shifts every 2× upsampling by half an output
// pixel towards the top left; BlazePose's segmentation head upsamples
// five times, 8 → 256 (docs/cvsm.md, "A learned landmark model beside the fit").
#include <cstddef>
#include <cstdint>
#include <set>
#include <vector>

namespace spinewatch::landmarks {

// Indices, within subgraph 0, of the RESIZE_BILINEAR operators with
// half_pixel_centers set.
std::set<std::size_t> half_pixel_resizes(const std::vector<std::uint8_t>& model);

}  // namespace spinewatch::landmarks

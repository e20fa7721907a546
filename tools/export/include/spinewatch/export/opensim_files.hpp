#pragma once
// The vertebra poses of a stretch of the posture stream as OpenSim files
// (docs/exposure.md, "Export for researchers"):
//   spine.mot  motion: time, L5's rotation in the world, then each
//              intervertebral joint's flexion, lateral bend and axial
//              rotation (degrees), L4_L5 up to T1_T2;
//   spine.trc  markers T1…L5 at the vertebral body centres, mm.
// OpenSim's ground frame (X forward, Y up, Z right) is the ISB frame of
// docs/interfaces.md §1 already: coordinates are written as they are.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::exporting {

// One tracked posture: the only kind exported (init and lost pairs are
// omitted rows, not NaN: OpenSim's tools take a time column with gaps).
struct PoseRow {
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;  // the stream's clock; the files' time is t_ns / 1e9
  SpinePose pose;
};

// The .mot's column labels after "time", in order (51: 17 × 3).
std::vector<std::string> mot_columns();
// Samples per second of the rows: 1 / the median time step (0 for fewer than two rows).
double row_rate_hz(const std::vector<PoseRow>& rows);

// `name` is the first header line (OpenSim shows it as the motion's name).
std::string mot_text(const std::vector<PoseRow>& rows, std::string_view name);
// `file_name` is named on the PathFileType line, as motion-capture software writes it.
std::string trc_text(const std::vector<PoseRow>& rows, std::string_view file_name);

}  // namespace spinewatch::exporting

#include <fstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::phantom {

Status write_recording(const PhantomSequence& sequence, const std::filesystem::path& dir) {
  const FrameFormat format = FrameFormat::packed(PixelFormat::YUYV, kImageWidth, kImageHeight);
  auto writer = RecordingWriter::create(dir, format, kPhantomFps);
  if (!writer) return writer.error();

  const auto truth_path = dir / "ground_truth.ndjson";
  std::ofstream truth(truth_path, std::ios::binary | std::ios::trunc);
  if (!truth) return Error{fmt::format("{}: cannot create", truth_path.string())};

  for (int index = 0; index < sequence.frame_count(); ++index) {
    const PhantomFrame frame = sequence.render(index);
    const FrameInfo info{frame.seq, frame.t_ns};
    for (View view : kViews)
      if (auto s = writer->write(view, Frame::owning(format, info, to_yuyv(frame.luma[static_cast<int>(view)]))); !s)
        return s;
    truth << encode_posture(frame.truth) << '\n';
  }
  truth.flush();
  if (!truth) return Error{fmt::format("{}: write failed", truth_path.string())};

  for (View view : kViews) {
    const auto png = dir / fmt::format("background_{}.png", view == View::Frontal ? "frontal" : "lateral");
    bool written = false;
    try {
      written = cv::imwrite(png.string(), sequence.background(view));
    } catch (const cv::Exception& e) {
      return Error{fmt::format("{}: {}", png.string(), e.what())};
    }
    if (!written) return Error{fmt::format("{}: cannot write", png.string())};
  }
  if (auto s = save_calibration(dir / "calibration.yaml", sequence.options().rig); !s) return s;
  return writer->finish(sequence.subject_json(), sequence.notes());
}

}  // namespace spinewatch::phantom

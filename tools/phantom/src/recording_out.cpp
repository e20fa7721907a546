#include <fstream>

#include <fmt/format.h>

#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/phantom/compression.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::phantom {

Status write_recording(const PhantomSequence& sequence, const std::filesystem::path& dir) {
  const FrameFormat format = FrameFormat::packed(PixelFormat::YUYV, kImageWidth, kImageHeight);
  auto writer = RecordingWriter::create(dir, format, kPhantomFps);
  if (!writer) return writer.error();

  const auto truth_path = dir / "ground_truth.ndjson";
  std::ofstream truth(truth_path, std::ios::binary | std::ios::trunc);
  if (!truth) return Error{fmt::format("{}: cannot create", truth_path.string())};

  // With compression, each view's frames through its own H.264 stream, in order.
  std::vector<H264RoundTrip> streams;
  if (const auto crf = sequence.options().h264_crf)
    for (int view = 0; view < 2; ++view) {
      auto stream = H264RoundTrip::create({kImageWidth, kImageHeight}, *crf);
      if (!stream) return stream.error();
      streams.push_back(std::move(stream).value());
    }

  for (int index = 0; index < sequence.frame_count(); ++index) {
    PhantomFrame frame = sequence.render(index);
    for (std::size_t view = 0; view < streams.size(); ++view) {
      auto coded = streams[view].pass(frame.luma[view], frame.chroma[view]);
      if (!coded) return coded.error();
      frame.luma[view] = std::move(coded->luma);
      frame.chroma[view] = std::move(coded->chroma);
    }
    const FrameInfo info{frame.seq, frame.t_ns};
    for (View view : kViews)
      if (auto s = writer->write(view, Frame::owning(format, info, yuyv_bytes(frame, static_cast<int>(view)))); !s)
        return s;
    truth << encode_posture(frame.truth) << '\n';
  }
  truth.flush();
  if (!truth) return Error{fmt::format("{}: write failed", truth_path.string())};

  // The empty scene as the cameras see it without noise: grey, or with
  // colour as YUYV (the capture module's writer turns it into a colour PNG).
  const BackgroundImages images{stored_background(sequence, View::Frontal), stored_background(sequence, View::Lateral)};
  if (auto s = write_background_images(dir, images); !s) return s;
  if (auto s = save_calibration(dir / "calibration.yaml", sequence.options().rig); !s) return s;
  return writer->finish(sequence.subject_json(), sequence.notes());
}

}  // namespace spinewatch::phantom

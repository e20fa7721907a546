#include "source/recording_pair_source.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/recording_source.hpp"
#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch {
namespace {

class RecordingPairSource final : public PairSource {
 public:
  RecordingPairSource(RecordingSource source, std::string description)
      : source_(std::move(source)),
        pairer_(sync::PairerOptions{.fps = source_.info().fps}),
        description_(std::move(description)) {}

  std::optional<FramePair> next() override {
    for (;;) {
      if (auto pair = pairer_.pop()) return pair;
      if (ended_) return std::nullopt;
      auto frame = source_.next();
      if (!frame) {
        ended_ = true;
        pairer_.flush();
      } else {
        pairer_.push(frame->view, std::move(frame->frame));
      }
      publish_stats();
    }
  }

  void stop() override { source_.stop(); }

  SourceStats stats() const override {
    SourceStats s{frames_.load(), frames_lost_.load(), {}};
    for (int i = 0; i < 2; ++i) s.camera[i].frames = view_frames_[i].load(std::memory_order_relaxed);
    return s;
  }

  std::string describe() const override { return description_; }

 private:
  void publish_stats() {
    const auto& s = pairer_.stats();
    std::uint64_t lost = 0;
    for (const auto& d : s.drops) lost += d.total_discarded() + d.sequence_gaps;
    frames_.store(s.frames_in[0] + s.frames_in[1], std::memory_order_relaxed);
    frames_lost_.store(lost, std::memory_order_relaxed);
    for (int i = 0; i < 2; ++i) view_frames_[i].store(s.frames_in[i], std::memory_order_relaxed);
  }

  RecordingSource source_;
  sync::FramePairer pairer_;
  std::string description_;
  bool ended_ = false;
  std::atomic<std::uint64_t> frames_{0}, frames_lost_{0};
  std::atomic<std::uint64_t> view_frames_[2] = {0, 0};
};

}  // namespace

Result<std::unique_ptr<PairSource>> open_recording_pair_source(const std::filesystem::path& dir,
                                                               RecordingPairOptions options) {
  auto source = RecordingSource::open(dir, RecordingSourceOptions{.paced = options.paced, .loop = options.loop});
  if (!source) return source.error();
  std::string description = fmt::format("recording {}", dir.string());
  return std::unique_ptr<PairSource>(std::make_unique<RecordingPairSource>(std::move(source).value(), std::move(description)));
}

}  // namespace spinewatch

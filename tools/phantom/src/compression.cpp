#include "spinewatch/phantom/compression.hpp"

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

namespace spinewatch::phantom {
namespace {

struct ContextFree {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameFree {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketFree {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
using ContextPtr = std::unique_ptr<AVCodecContext, ContextFree>;
using FramePtr = std::unique_ptr<AVFrame, FrameFree>;
using PacketPtr = std::unique_ptr<AVPacket, PacketFree>;

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

}  // namespace

struct H264RoundTrip::Codec {
  ContextPtr encoder, decoder;
  FramePtr in, out;
  PacketPtr packet;
  cv::Size size;
  std::int64_t next_pts = 0;
};

H264RoundTrip::H264RoundTrip(std::unique_ptr<Codec> codec) : codec_(std::move(codec)) {}
H264RoundTrip::H264RoundTrip(H264RoundTrip&&) noexcept = default;
H264RoundTrip& H264RoundTrip::operator=(H264RoundTrip&&) noexcept = default;
H264RoundTrip::~H264RoundTrip() = default;

Result<H264RoundTrip> H264RoundTrip::create(cv::Size size, int crf) {
  if (crf < kMinCrf || crf > kMaxCrf) return Error{fmt::format("h264: CRF {} is out of range [{}, {}]", crf, kMinCrf, kMaxCrf)};
  if (size.width % 2 || size.height % 2) return Error{"h264: the frame size must be even for 4:2:0"};
  av_log_set_level(AV_LOG_ERROR);  // x264 reports its statistics at info level on every close
  const AVCodec* x264 = avcodec_find_encoder_by_name("libx264");
  const AVCodec* h264 = avcodec_find_decoder(AV_CODEC_ID_H264);
  if (!x264 || !h264)
    return Error{"h264: this machine's libavcodec has no libx264 encoder or no H.264 decoder (Debian's libavcodec59 has both)"};
  auto codec = std::make_unique<Codec>();
  codec->size = size;
  codec->encoder.reset(avcodec_alloc_context3(x264));
  codec->decoder.reset(avcodec_alloc_context3(h264));
  codec->in.reset(av_frame_alloc());
  codec->out.reset(av_frame_alloc());
  codec->packet.reset(av_packet_alloc());
  if (!codec->encoder || !codec->decoder || !codec->in || !codec->out || !codec->packet) return Error{"h264: out of memory"};
  AVCodecContext* e = codec->encoder.get();
  e->width = size.width;
  e->height = size.height;
  e->pix_fmt = AV_PIX_FMT_YUV420P;
  e->time_base = AVRational{1, 30};
  e->framerate = AVRational{30, 1};
  e->gop_size = 60;  // an intra frame every 2 s, as webcams do
  e->max_b_frames = 0;
  e->thread_count = 1;  // the same bytes on every machine
  av_opt_set(e->priv_data, "preset", "veryfast", 0);
  av_opt_set(e->priv_data, "tune", "zerolatency", 0);
  av_opt_set(e->priv_data, "crf", std::to_string(crf).c_str(), 0);
  if (int r = avcodec_open2(e, x264, nullptr); r < 0) return Error{"h264: cannot open libx264: " + av_message(r)};
  codec->decoder->thread_count = 1;
  codec->decoder->flags |= AV_CODEC_FLAG_LOW_DELAY;
  if (int r = avcodec_open2(codec->decoder.get(), h264, nullptr); r < 0)
    return Error{"h264: cannot open the H.264 decoder: " + av_message(r)};
  AVFrame* f = codec->in.get();
  f->format = AV_PIX_FMT_YUV420P;
  f->width = size.width;
  f->height = size.height;
  if (int r = av_frame_get_buffer(f, 0); r < 0) return Error{"h264: " + av_message(r)};
  return H264RoundTrip(std::move(codec));
}

Result<CodedFrame> H264RoundTrip::pass(const cv::Mat& luma, const cv::Mat& chroma) {
  Codec& c = *codec_;
  if (luma.size() != c.size || luma.type() != CV_8U) return Error{"h264: a frame of another size or type"};
  AVFrame* in = c.in.get();
  if (int r = av_frame_make_writable(in); r < 0) return Error{"h264: " + av_message(r)};
  for (int y = 0; y < c.size.height; ++y) std::copy_n(luma.ptr<std::uint8_t>(y), c.size.width, in->data[0] + y * in->linesize[0]);
  const cv::Size half(c.size.width / 2, c.size.height / 2);
  cv::Mat uv(half, CV_8UC2, cv::Scalar(128, 128));
  if (!chroma.empty()) cv::resize(chroma, uv, half, 0, 0, cv::INTER_AREA);  // 4:2:0, each 2 × 2 block's mean
  for (int y = 0; y < half.height; ++y) {
    const cv::Vec2b* row = uv.ptr<cv::Vec2b>(y);
    for (int x = 0; x < half.width; ++x) {
      in->data[1][y * in->linesize[1] + x] = row[x][0];
      in->data[2][y * in->linesize[2] + x] = row[x][1];
    }
  }
  in->pts = c.next_pts++;
  if (int r = avcodec_send_frame(c.encoder.get(), in); r < 0) return Error{"h264: encoding: " + av_message(r)};
  if (int r = avcodec_receive_packet(c.encoder.get(), c.packet.get()); r < 0)
    return Error{"h264: the encoder held a frame back: " + av_message(r)};
  const int sent = avcodec_send_packet(c.decoder.get(), c.packet.get());
  av_packet_unref(c.packet.get());
  if (sent < 0) return Error{"h264: decoding: " + av_message(sent)};
  AVFrame* out = c.out.get();
  if (int r = avcodec_receive_frame(c.decoder.get(), out); r < 0)
    return Error{"h264: the decoder held a frame back: " + av_message(r)};
  CodedFrame coded;
  coded.luma.create(c.size, CV_8U);
  for (int y = 0; y < c.size.height; ++y)
    std::copy_n(out->data[0] + y * out->linesize[0], c.size.width, coded.luma.ptr<std::uint8_t>(y));
  if (!chroma.empty()) {
    cv::Mat decoded(half, CV_8UC2);
    for (int y = 0; y < half.height; ++y)
      for (int x = 0; x < half.width; ++x)
        decoded.at<cv::Vec2b>(y, x) = {out->data[1][y * out->linesize[1] + x], out->data[2][y * out->linesize[2] + x]};
    cv::resize(decoded, coded.chroma, c.size, 0, 0, cv::INTER_LINEAR);
  }
  av_frame_unref(out);
  return coded;
}

}  // namespace spinewatch::phantom

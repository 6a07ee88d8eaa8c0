// A video file as a frame source (frame_source.h): FFmpeg's demuxer and decoder, each frame
// converted to packed RGB by libswscale into one buffer the view points at.
#include <chrono>
#include <memory>

#include "patlab/core/error.h"
#include "patlab/live/frame_source.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

namespace patlab::live {

namespace {

std::string AvError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

struct FormatCloser {
  void operator()(AVFormatContext* c) const { avformat_close_input(&c); }
};
struct CodecFreer {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameFreer {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketFreer {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct ScaleFreer {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};

class VideoSource : public FrameSource {
 public:
  explicit VideoSource(const std::string& path) : name_(path) { Open(); }

  bool Next(SourceFrame* frame) override {
    if (!Decode()) return false;
    if ((frame_->flags & AV_FRAME_FLAG_CORRUPT) != 0 || frame_->decode_error_flags != 0) {
      throw CorruptFrameError(name_ + ": frame " + std::to_string(read_ - 1) +
                              " skipped: the decoder flags it corrupt");
    }
    Convert();
    const double pts_s = PresentationSeconds();
    if (index_ == 0) {
      first_pts_s_ = pts_s;
      start_wall_s_ = WallTimeSeconds();
    }
    frame->data = rgb_.data();
    frame->width_px = width_;
    frame->height_px = height_;
    frame->stride_bytes = static_cast<std::ptrdiff_t>(width_) * 3;
    frame->format = camera::PixelFormat::kRgb8;
    frame->media_time_s = pts_s - first_pts_s_;
    frame->capture_time_s = start_wall_s_ + frame->media_time_s;
    frame->index = index_++;
    return true;
  }
  const std::string& name() const override { return name_; }

 private:
  [[noreturn]] void Fail(const std::string& what, int code) const {
    throw InputError(name_ + ": " + what + (code < 0 ? ": " + AvError(code) : std::string()) +
                     "; expected a video file FFmpeg can decode");
  }

  void Open() {
    // FFmpeg's own log lines (its guesses about a broken file) would interleave with patlab's
    // messages on stderr; every failure is reported by the InputError below instead.
    av_log_set_level(AV_LOG_QUIET);
    AVFormatContext* format = nullptr;
    int rc = avformat_open_input(&format, name_.c_str(), nullptr, nullptr);
    if (rc < 0) Fail("cannot open", rc);
    format_.reset(format);
    if ((rc = avformat_find_stream_info(format, nullptr)) < 0) Fail("no stream information", rc);
    const AVCodec* codec = nullptr;
    stream_ = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
    if (stream_ < 0 || codec == nullptr) Fail("no video stream", stream_);
    codec_.reset(avcodec_alloc_context3(codec));
    if (!codec_) throw EnvironmentError(name_ + ": cannot allocate a decoder");
    // Frames the decoder knows to be damaged come out flagged (AV_FRAME_FLAG_CORRUPT), so that
    // Next can skip and count them rather than the decoder dropping them unseen.
    codec_->flags |= AV_CODEC_FLAG_OUTPUT_CORRUPT;
    rc = avcodec_parameters_to_context(codec_.get(), format->streams[stream_]->codecpar);
    if (rc < 0 || (rc = avcodec_open2(codec_.get(), codec, nullptr)) < 0) {
      Fail("cannot open the decoder", rc);
    }
    width_ = codec_->width;
    height_ = codec_->height;
    if (width_ <= 0 || height_ <= 0) Fail("the video has no frame size", 0);
    frame_.reset(av_frame_alloc());
    packet_.reset(av_packet_alloc());
    rgb_.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  }

  // The next decoded frame into frame_; false at the end of the stream (decoder drained).
  // CorruptFrameError for a packet or frame the decoder rejects (the next call goes on after it);
  // SourceError (not reopenable: a file would replay) when reading the file fails before its end.
  bool Decode() {
    while (true) {
      const int rc = avcodec_receive_frame(codec_.get(), frame_.get());
      if (rc == 0) {
        ++read_;
        return true;
      }
      if (rc == AVERROR_EOF) return false;
      if (rc != AVERROR(EAGAIN)) Skip("cannot decode a frame", rc);
      if (draining_) return false;
      Feed();
    }
  }

  [[noreturn]] void Skip(const std::string& what, int code) {
    throw CorruptFrameError(name_ + ": frame " + std::to_string(read_++) + " skipped: " + what +
                            ": " + AvError(code));
  }

  // Sends the next packet of the video stream to the decoder, or the end of the stream.
  void Feed() {
    while (true) {
      const int rc = av_read_frame(format_.get(), packet_.get());
      if (rc < 0) {
        draining_ = true;
        avcodec_send_packet(codec_.get(), nullptr);
        if (rc != AVERROR_EOF) {
          throw SourceError(name_ + ": reading the file failed: " + AvError(rc), false);
        }
        return;
      }
      const bool ours = packet_->stream_index == stream_;
      const int sent = ours ? avcodec_send_packet(codec_.get(), packet_.get()) : 0;
      av_packet_unref(packet_.get());
      if (sent < 0) Skip("cannot decode a packet", sent);
      if (ours) return;
    }
  }

  void Convert() {
    if (frame_->width != width_ || frame_->height != height_) {
      Fail("the frame size changes within the video", 0);
    }
    scale_.reset(sws_getCachedContext(scale_.release(), width_, height_,
                                      static_cast<AVPixelFormat>(frame_->format), width_, height_,
                                      AV_PIX_FMT_RGB24, SWS_BILINEAR, nullptr, nullptr, nullptr));
    if (!scale_) Fail("cannot convert its pixel format to RGB", 0);
    uint8_t* planes[4] = {rgb_.data(), nullptr, nullptr, nullptr};
    const int strides[4] = {width_ * 3, 0, 0, 0};
    sws_scale(scale_.get(), frame_->data, frame_->linesize, 0, height_, planes, strides);
  }

  double PresentationSeconds() const {
    const int64_t pts = frame_->best_effort_timestamp;
    if (pts == AV_NOPTS_VALUE) return static_cast<double>(index_) / 30.0;
    return static_cast<double>(pts) * av_q2d(format_->streams[stream_]->time_base);
  }

  std::string name_;
  std::unique_ptr<AVFormatContext, FormatCloser> format_;
  std::unique_ptr<AVCodecContext, CodecFreer> codec_;
  std::unique_ptr<AVFrame, FrameFreer> frame_;
  std::unique_ptr<AVPacket, PacketFreer> packet_;
  std::unique_ptr<SwsContext, ScaleFreer> scale_;
  int stream_ = -1;
  int width_ = 0, height_ = 0;
  bool draining_ = false;
  std::vector<uint8_t> rgb_;
  int64_t index_ = 0;  // frames delivered
  int64_t read_ = 0;   // frames the decoder gave or rejected, for messages
  double first_pts_s_ = 0.0, start_wall_s_ = 0.0;
};

}  // namespace

std::unique_ptr<FrameSource> OpenVideoFile(const std::string& path) {
  return std::make_unique<VideoSource>(path);
}

}  // namespace patlab::live

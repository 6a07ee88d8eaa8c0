// FFV1 and MJPEG video writing for the tests (video_writer.h).
#include "video_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

namespace patlab::live::testing {

namespace {

struct Writer {
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  SwsContext* scale = nullptr;
  AVFrame* frame = av_frame_alloc();
  AVPacket* packet = av_packet_alloc();

  ~Writer() {
    if (format && format->pb) avio_closep(&format->pb);
    avformat_free_context(format);
    avcodec_free_context(&codec);
    sws_freeContext(scale);
    av_frame_free(&frame);
    av_packet_free(&packet);
  }

  bool Open(const std::string& path, int width, int height, int fps, AVCodecID id,
            AVPixelFormat pixels) {
    if (avformat_alloc_output_context2(&format, nullptr, "matroska", path.c_str()) < 0)
      return false;
    const AVCodec* encoder = avcodec_find_encoder(id);
    if (!encoder) return false;
    stream = avformat_new_stream(format, nullptr);
    codec = avcodec_alloc_context3(encoder);
    codec->width = width;
    codec->height = height;
    codec->pix_fmt = pixels;
    codec->time_base = AVRational{1, fps};
    stream->time_base = codec->time_base;
    if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    if (avcodec_open2(codec, encoder, nullptr) < 0) return false;
    if (avcodec_parameters_from_context(stream->codecpar, codec) < 0) return false;
    if (avio_open(&format->pb, path.c_str(), AVIO_FLAG_WRITE) < 0) return false;
    scale = sws_getContext(width, height, AV_PIX_FMT_RGB24, width, height, pixels, SWS_POINT,
                           nullptr, nullptr, nullptr);
    frame->format = pixels;
    frame->width = width;
    frame->height = height;
    return scale && av_frame_get_buffer(frame, 0) >= 0 &&
           avformat_write_header(format, nullptr) >= 0;
  }

  bool Drain() {
    while (true) {
      const int rc = avcodec_receive_packet(codec, packet);
      if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return true;
      if (rc < 0) return false;
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      if (av_interleaved_write_frame(format, packet) < 0) return false;
    }
  }

  bool Add(const camera::Image& image, int64_t pts) {
    if (av_frame_make_writable(frame) < 0) return false;
    const uint8_t* source[1] = {image.data.data()};
    const int stride[1] = {image.RowBytes()};
    sws_scale(scale, source, stride, 0, image.height_px, frame->data, frame->linesize);
    frame->pts = pts;
    return avcodec_send_frame(codec, frame) >= 0 && Drain();
  }

  bool Finish() {
    return avcodec_send_frame(codec, nullptr) >= 0 && Drain() && av_write_trailer(format) >= 0;
  }
};

}  // namespace

namespace {

bool Write(const std::string& path, const std::vector<camera::Image>& frames, int fps, AVCodecID id,
           AVPixelFormat pixels) {
  if (frames.empty()) return false;
  av_log_set_level(AV_LOG_ERROR);  // not swscale's note on the JPEG range of YUVJ420P
  Writer writer;
  if (!writer.Open(path, frames[0].width_px, frames[0].height_px, fps, id, pixels)) return false;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (!writer.Add(frames[i], static_cast<int64_t>(i))) return false;
  }
  return writer.Finish();
}

}  // namespace

bool WriteLosslessVideo(const std::string& path, const std::vector<camera::Image>& frames,
                        int fps) {
  return Write(path, frames, fps, AV_CODEC_ID_FFV1, AV_PIX_FMT_RGB32);
}

bool WriteMjpegVideo(const std::string& path, const std::vector<camera::Image>& frames, int fps) {
  return Write(path, frames, fps, AV_CODEC_ID_MJPEG, AV_PIX_FMT_YUVJ420P);
}

}  // namespace patlab::live::testing

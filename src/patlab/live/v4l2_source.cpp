// A V4L2 device as a frame source (frame_source.h), through libv4l2, which converts the
// camera's pixel format (YUYV, MJPEG, Bayer, ...) to the RGB24 asked for. Streaming I/O with
// memory-mapped buffers: four buffers queued, the newest dequeued one handed out and requeued on
// the next call. Compiled here but not run against a device (docs/live.md).
#include <fcntl.h>
#include <libv4l2.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/live/frame_source.h"

namespace patlab::live {

namespace {

class V4l2Source : public FrameSource {
 public:
  V4l2Source(const std::string& path, const FrameSourceOptions& options) : name_(path) {
    fd_ = v4l2_open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd_ < 0) {
      throw InputError(path + ": cannot open the device: " + std::strerror(errno) +
                       "; expected a V4L2 video capture device");
    }
    try {
      SetFormat(options);
      MapBuffers();
      v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      Ioctl(VIDIOC_STREAMON, &type, "VIDIOC_STREAMON");
    } catch (...) {
      Release();
      throw;
    }
  }
  ~V4l2Source() override { Release(); }

  bool Next(SourceFrame* frame) override {
    // A failure here (ENODEV when the camera is unplugged, EIO) is a SourceError: the live loop
    // closes the device and opens it again with a back-off.
    if (queued_index_ >= 0) {
      v4l2_buffer back = Buffer(static_cast<uint32_t>(queued_index_));
      queued_index_ = -1;
      Ioctl(VIDIOC_QBUF, &back, "VIDIOC_QBUF", true);
    }
    v4l2_buffer buffer = Buffer(0);
    Ioctl(VIDIOC_DQBUF, &buffer, "VIDIOC_DQBUF", true);
    queued_index_ = static_cast<int>(buffer.index);
    if (buffer.flags & V4L2_BUF_FLAG_ERROR) {
      throw CorruptFrameError(name_ + ": the device flagged buffer " +
                              std::to_string(buffer.index) + " as corrupt");
    }
    frame->data = static_cast<const uint8_t*>(buffers_[buffer.index].start);
    frame->width_px = width_;
    frame->height_px = height_;
    frame->stride_bytes = stride_;
    frame->format = camera::PixelFormat::kRgb8;
    // The driver's timestamp is CLOCK_MONOTONIC; the wall time of the dequeue stands for it.
    const double stamp_s =
        static_cast<double>(buffer.timestamp.tv_sec) + 1e-6 * buffer.timestamp.tv_usec;
    if (index_ == 0) first_stamp_s_ = stamp_s;
    frame->media_time_s = stamp_s - first_stamp_s_;
    frame->capture_time_s = WallTimeSeconds();
    frame->index = index_++;
    return true;
  }
  const std::string& name() const override { return name_; }

 private:
  struct Mapped {
    void* start = nullptr;
    size_t length = 0;
  };

  // `streaming`: a failure while frames flow, which a reopen may cure (SourceError).
  void Ioctl(unsigned long request, void* arg, const char* what, bool streaming = false) const {
    int rc;
    do {
      rc = v4l2_ioctl(fd_, request, arg);
    } while (rc < 0 && errno == EINTR);
    if (rc < 0) {
      const std::string message = name_ + ": " + what + " failed: " + std::strerror(errno);
      if (streaming) throw SourceError(message, true);
      throw EnvironmentError(message);
    }
  }

  static v4l2_buffer Buffer(uint32_t index) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = index;
    return b;
  }

  void SetFormat(const FrameSourceOptions& options) {
    v4l2_format format{};
    format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    Ioctl(VIDIOC_G_FMT, &format, "VIDIOC_G_FMT");
    if (options.device_width_px > 0) format.fmt.pix.width = options.device_width_px;
    if (options.device_height_px > 0) format.fmt.pix.height = options.device_height_px;
    format.fmt.pix.pixelformat = V4L2_PIX_FMT_RGB24;
    format.fmt.pix.field = V4L2_FIELD_ANY;
    Ioctl(VIDIOC_S_FMT, &format, "VIDIOC_S_FMT");
    if (format.fmt.pix.pixelformat != V4L2_PIX_FMT_RGB24) {
      throw InputError(name_ + ": the device gives no RGB24 frames, even through libv4l2; " +
                       "expected a camera libv4l2 can convert");
    }
    width_ = static_cast<int>(format.fmt.pix.width);
    height_ = static_cast<int>(format.fmt.pix.height);
    stride_ = format.fmt.pix.bytesperline > 0 ? format.fmt.pix.bytesperline : width_ * 3;
  }

  void MapBuffers() {
    v4l2_requestbuffers request{};
    request.count = 4;
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.memory = V4L2_MEMORY_MMAP;
    Ioctl(VIDIOC_REQBUFS, &request, "VIDIOC_REQBUFS");
    for (uint32_t i = 0; i < request.count; ++i) {
      v4l2_buffer buffer = Buffer(i);
      Ioctl(VIDIOC_QUERYBUF, &buffer, "VIDIOC_QUERYBUF");
      void* start = v4l2_mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_,
                              buffer.m.offset);
      if (start == MAP_FAILED) {
        throw EnvironmentError(name_ + ": cannot map a buffer: " + std::strerror(errno));
      }
      buffers_.push_back({start, buffer.length});
      Ioctl(VIDIOC_QBUF, &buffer, "VIDIOC_QBUF");
    }
  }

  void Release() {
    if (fd_ < 0) return;
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    v4l2_ioctl(fd_, VIDIOC_STREAMOFF, &type);
    for (const Mapped& m : buffers_) v4l2_munmap(m.start, m.length);
    buffers_.clear();
    v4l2_close(fd_);
    fd_ = -1;
  }

  std::string name_;
  int fd_ = -1;
  int width_ = 0, height_ = 0;
  std::ptrdiff_t stride_ = 0;
  std::vector<Mapped> buffers_;
  int queued_index_ = -1;
  int64_t index_ = 0;
  double first_stamp_s_ = 0.0;
};

}  // namespace

std::unique_ptr<FrameSource> OpenV4l2Device(const std::string& path,
                                            const FrameSourceOptions& options) {
  return std::make_unique<V4l2Source>(path, options);
}

}  // namespace patlab::live

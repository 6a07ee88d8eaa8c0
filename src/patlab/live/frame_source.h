// Where a live camera's frames come from, behind one interface: a list of frame files (what
// `patlab detect` reads: files, directories, .txt lists; vision/frame_io.h), a video file
// decoded by FFmpeg (libavformat, libavcodec, libswscale; any container and codec the system's
// FFmpeg reads, decoded to RGB), or a V4L2 device (/dev/videoN) through libv4l2, which converts
// the camera's own pixel format to RGB. Each source hands out the next frame as a strided view
// and its capture time.
//
// The V4L2 source is compiled and its set-up errors are reported, but it has not been run
// against a device on the machines patlab is tested on (no camera, and v4l2loopback needs a
// kernel module): docs/live.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "patlab/camera/image.h"
#include "patlab/core/error.h"

namespace patlab::live {

// A frame as a source holds it; valid until the source's next call.
struct SourceFrame {
  const uint8_t* data = nullptr;
  int width_px = 0;
  int height_px = 0;
  std::ptrdiff_t stride_bytes = 0;  // bytes from one row's start to the next's
  camera::PixelFormat format = camera::PixelFormat::kRgb8;
  // When the frame was captured, seconds since the Unix epoch: a device's buffer timestamp; a
  // video's presentation time added to the wall time at which its first frame was read; a frame
  // file's read time.
  double capture_time_s = 0.0;
  // Seconds from the source's first frame at the source's own pace (a video's presentation time,
  // a frame list's 1 / list_rate_hz steps, a device's timestamps): what --rate native paces by.
  double media_time_s = 0.0;
  int64_t index = 0;  // 0, 1, 2, ... in the order delivered
};

struct FrameSourceOptions {
  int raw_width_px = 0;  // size of raw UYVY frame files (see vision::FrameDetectorOptions)
  int raw_height_px = 0;
  // A frame list starts again after its last frame (with a frame limit, to replay a few frames).
  bool loop = false;
  // The pace of a frame list under --rate native (frames carry no time of their own), > 0.
  double list_rate_hz = 60.0;
  // A V4L2 device's requested size (0: the device's current size) and frame rate.
  int device_width_px = 0;
  int device_height_px = 0;
};

// A frame the source read but could not decode (a corrupt video packet, a frame flagged corrupt
// by the decoder, a device buffer flagged as an error): the source skips it and goes on; calling
// Next again gives the next frame. The live loop counts these (LiveStats::skipped).
class CorruptFrameError : public InputError {
 public:
  using InputError::InputError;
};

// The source failed while delivering frames (a V4L2 device gone, a failing read): it cannot go
// on. `reopenable`: opening the source again may bring it back (a device); false for a file,
// which would replay from its start, and ends there instead (live_loop.h).
class SourceError : public EnvironmentError {
 public:
  SourceError(const std::string& message, bool reopenable)
      : EnvironmentError(message), reopenable_(reopenable) {}
  bool reopenable() const { return reopenable_; }

 private:
  bool reopenable_;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame; false at the end of a file source. CorruptFrameError for a frame it skips
  // (call again for the next), SourceError when it fails (a device gone, a read error); InputError
  // for a bad frame file.
  virtual bool Next(SourceFrame* frame) = 0;
  // The source as given, for messages.
  virtual const std::string& name() const = 0;
};

// The kind of source a SOURCE argument names: "/dev/..." or "v4l2:PATH" a V4L2 device; a file
// whose name ends in .mp4 .mkv .avi .mov .webm .m4v .mpg .mpeg .ts (any case) a video; anything
// else a frame list argument.
enum class SourceKind { kFrames, kVideo, kDevice };
SourceKind KindOfSource(const std::string& spec);

// Opens a source. InputError naming the source when it cannot be opened or read (missing file,
// no video stream, a device that refuses RGB).
std::unique_ptr<FrameSource> OpenFrameSource(const std::string& spec,
                                             const FrameSourceOptions& options);

// Frames of a video file in the order they play; exposed for tests and tools that do not need a
// live loop. Every decoded frame is converted to packed RGB.
std::unique_ptr<FrameSource> OpenVideoFile(const std::string& path);
std::unique_ptr<FrameSource> OpenFrameList(const std::string& spec,
                                           const FrameSourceOptions& options);
std::unique_ptr<FrameSource> OpenV4l2Device(const std::string& path,
                                            const FrameSourceOptions& options);

// Copies a view into `image` (resized as needed; no allocation once it has the size).
void CopyToImage(const SourceFrame& frame, camera::Image* image);

// Seconds since the Unix epoch, from the system clock.
double WallTimeSeconds();

}  // namespace patlab::live

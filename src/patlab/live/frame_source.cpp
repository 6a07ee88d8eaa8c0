// The frame-list source and what every source shares (frame_source.h). Videos: video_source.cpp;
// devices: v4l2_source.cpp.
#include "patlab/live/frame_source.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/vision/frame_io.h"

namespace patlab::live {

namespace {

class FrameListSource : public FrameSource {
 public:
  FrameListSource(const std::string& spec, const FrameSourceOptions& options)
      : name_(spec), options_(options), paths_(vision::ExpandFrameList({spec})) {}

  bool Next(SourceFrame* frame) override {
    if (next_ >= paths_.size()) {
      if (!options_.loop) return false;
      next_ = 0;
    }
    image_ = vision::ReadFrameFile(paths_[next_++], options_.raw_width_px, options_.raw_height_px);
    frame->data = image_.data.data();
    frame->width_px = image_.width_px;
    frame->height_px = image_.height_px;
    frame->stride_bytes = image_.RowBytes();
    frame->format = image_.format;
    frame->capture_time_s = WallTimeSeconds();
    frame->media_time_s = static_cast<double>(index_) / options_.list_rate_hz;
    frame->index = index_++;
    return true;
  }
  const std::string& name() const override { return name_; }

 private:
  std::string name_;
  FrameSourceOptions options_;
  std::vector<std::string> paths_;
  size_t next_ = 0;
  int64_t index_ = 0;
  camera::Image image_;
};

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

double WallTimeSeconds() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  return std::chrono::duration<double>(now).count();
}

SourceKind KindOfSource(const std::string& spec) {
  if (spec.rfind("/dev/", 0) == 0 || spec.rfind("v4l2:", 0) == 0) return SourceKind::kDevice;
  const std::string lower = Lower(spec);
  for (const char* ext :
       {".mp4", ".mkv", ".avi", ".mov", ".webm", ".m4v", ".mpg", ".mpeg", ".ts"}) {
    if (EndsWith(lower, ext)) return SourceKind::kVideo;
  }
  return SourceKind::kFrames;
}

std::unique_ptr<FrameSource> OpenFrameList(const std::string& spec,
                                           const FrameSourceOptions& options) {
  if (!(options.list_rate_hz > 0.0)) {
    throw InputError("--list-rate is " + FormatNumber(options.list_rate_hz) +
                     "; expected > 0 frames per second");
  }
  return std::make_unique<FrameListSource>(spec, options);
}

std::unique_ptr<FrameSource> OpenFrameSource(const std::string& spec,
                                             const FrameSourceOptions& options) {
  switch (KindOfSource(spec)) {
    case SourceKind::kDevice:
      return OpenV4l2Device(spec.rfind("v4l2:", 0) == 0 ? spec.substr(5) : spec, options);
    case SourceKind::kVideo:
      return OpenVideoFile(spec);
    case SourceKind::kFrames:
      break;
  }
  return OpenFrameList(spec, options);
}

void CopyToImage(const SourceFrame& frame, camera::Image* image) {
  image->width_px = frame.width_px;
  image->height_px = frame.height_px;
  image->format = frame.format;
  const size_t row_bytes = static_cast<size_t>(image->RowBytes());
  image->data.resize(row_bytes * static_cast<size_t>(frame.height_px));
  for (int y = 0; y < frame.height_px; ++y) {
    std::memcpy(image->data.data() + row_bytes * static_cast<size_t>(y),
                frame.data + frame.stride_bytes * y, row_bytes);
  }
}

}  // namespace patlab::live

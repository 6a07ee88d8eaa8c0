// Side-by-side benchmark: our stages 2-4 (CMVision LUT -> runs -> union-find -> regions) against
// the OpenCV pipeline (cvtColor to YUV once, then per colour class cv::inRange +
// cv::connectedComponentsWithStats), on the same frames, one core. Prints both and the ratio.
//
//   build-vision/bench/vision_opencv_bench [frames_dir]   (default ../shared/frames if present)
//
// Built only when OpenCV is found (scripts/setup.sh --bench installs libopencv-dev).
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#ifdef PATLAB_BENCH_SPNG
#include <spng.h>
#endif

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/pipeline.h"
#include "patlab/vision/segment.h"

using namespace patlab;
using namespace patlab::vision;

namespace {

// This thread's CPU time in ms: on a shared machine wall time mostly measures the other jobs.
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

double last_min_ms = 0.0;  // the fastest run of the last MedianMs: the machine at its quietest

// Median CPU time of `reps` runs on this thread, in ms (OpenCV runs on this thread too:
// cv::setNumThreads(1)).
double MedianMs(const std::function<void()>& fn, int reps) {
  fn();  // warm-up: buffers grow once
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    const double start = ThreadCpuMs();
    fn();
    t.push_back(ThreadCpuMs() - start);
  }
  std::sort(t.begin(), t.end());
  last_min_ms = t.front();
  return t[static_cast<size_t>(reps / 2)];
}

// The SSL 2008 thresholds (tests/data/vision/ssl-2008.colors.txt), five YUV classes.
const char* kColors =
    "[Colors]\n(255,128,0) 0.5 1 orange\n(255,255,0) 0.6 5 yellow\n(0,0,255) 0.6 5 blue\n"
    "(255,0,255) 0.6 10 pink\n(0,255,128) 0.6 10 green\n[Thresholds]\n"
    "(60:160,60:115,160:200)\n(100:255,0:95,135:175)\n(30:160,150:255,60:125)\n"
    "(150:255,90:135,165:255)\n(70:180,105:150,0:100)\n";

// A synthetic field: green carpet with mild texture and 10 robots (SSL standard patterns) plus a
// ball, at the scale of the 2008 frame (about 5 mm per pixel).
patlab::camera::Image SyntheticField(int width, int height) {
  std::vector<patlab::render::Disc> discs;
  const patlab::render::Rgb blue{50, 75, 160}, yellow{255, 250, 120}, pink{248, 140, 135},
      green{30, 125, 75};
  const patlab::render::Rgb black{20, 20, 25};
  for (int i = 0; i < 10; ++i) {
    const Vec2 c(width * (0.1 + 0.08 * i), height * (0.2 + 0.06 * ((i * 7) % 10)));
    discs.push_back({c, 18, black});
    discs.push_back({c, 5, i < 5 ? blue : yellow});
    const double a = 0.3 * i;
    const double angles[4] = {0.96, -0.96, 2.57, -2.57};
    for (int k = 0; k < 4; ++k) {
      discs.push_back({c + 13.0 * Vec2(std::cos(a + angles[k]), std::sin(a + angles[k])), 4,
                       ((i >> k) & 1) ? pink : green});
    }
  }
  discs.push_back({Vec2(width * 0.6, height * 0.77), 2.5, {200, 113, 90}});
  patlab::camera::Image image = patlab::render::RenderDiscs(width, height, {40, 66, 21}, discs, 4);
  uint32_t state = 12345;  // texture: +-6 levels of deterministic noise
  for (uint8_t& v : image.data) {
    state = state * 1664525u + 1013904223u;
    const int n = static_cast<int>(state >> 28) - 8;
    v = static_cast<uint8_t>(std::clamp(v + n, 0, 255));
  }
  return image;
}

struct Result {
  double ours_ms, opencv_ms;
  long ours_regions, opencv_regions;
};

Result Compare(const patlab::camera::Image& frame, const Thresholds& thresholds) {
  SegmenterOptions options;
  options.min_area_px = 1;
  Segmenter segmenter(thresholds, options);
  Result r{};
  r.ours_ms = MedianMs([&] { segmenter.Process(frame); }, 200);
  r.ours_regions = segmenter.num_raw_regions();

  // OpenCV: the frame as a cv::Mat (no copy), YUV once, then per class inRange + CC with stats.
  const cv::Mat rgb(frame.height_px, frame.width_px, CV_8UC3,
                    const_cast<uint8_t*>(frame.data.data()));
  cv::Mat yuv, mask, labels, stats, centroids;
  long regions = 0;
  r.opencv_ms = MedianMs(
      [&] {
        regions = 0;
        cv::cvtColor(rgb, yuv, cv::COLOR_RGB2YUV);
        for (const ColorClass& c : thresholds.classes) {
          cv::inRange(yuv, cv::Scalar(c.range[0].lo, c.range[1].lo, c.range[2].lo),
                      cv::Scalar(c.range[0].hi, c.range[1].hi, c.range[2].hi), mask);
          regions +=
              cv::connectedComponentsWithStats(mask, labels, stats, centroids, 4, CV_32S) - 1;
        }
      },
      50);
  r.opencv_regions = regions;
  return r;
}

// OpenCV's way to the same regions: YUV once (from RGB, or from UYVY through RGB), then per
// class inRange + connectedComponentsWithStats.
double OpenCvMs(const patlab::camera::Image& frame, const Thresholds& thresholds) {
  const bool uyvy = frame.format == patlab::camera::PixelFormat::kUyvy;
  const cv::Mat in(frame.height_px, frame.width_px, uyvy ? CV_8UC2 : CV_8UC3,
                   const_cast<uint8_t*>(frame.data.data()));
  cv::Mat rgb, yuv, mask, labels, stats, centroids;
  return MedianMs(
      [&] {
        if (uyvy) {
          cv::cvtColor(in, rgb, cv::COLOR_YUV2RGB_UYVY);
          cv::cvtColor(rgb, yuv, cv::COLOR_RGB2YUV);
        } else {
          cv::cvtColor(in, yuv, cv::COLOR_RGB2YUV);
        }
        for (const ColorClass& c : thresholds.classes) {
          cv::inRange(yuv, cv::Scalar(c.range[0].lo, c.range[1].lo, c.range[2].lo),
                      cv::Scalar(c.range[0].hi, c.range[1].hi, c.range[2].hi), mask);
          cv::connectedComponentsWithStats(mask, labels, stats, centroids, 4, CV_32S);
        }
      },
      50);
}

#ifdef PATLAB_BENCH_SPNG
const char* kSpngNote = " beside libspng 0.7 (file read + decode to RGB)";
// libspng's time for a PNG at `path` (read and decoded to 8-bit RGB, alpha dropped: the frames
// here are opaque) and whether its pixels equal ReadFrame's `expected`.
std::string SpngColumn(const std::string& path, const patlab::camera::Image& expected) {
  if (path.size() < 4 || path.substr(path.size() - 4) != ".png") return "-";
  std::vector<uint8_t> pixels;
  const double ms = MedianMs(
      [&] {
        const std::vector<uint8_t> bytes = ReadFileBytes(path);
        spng_ctx* ctx = spng_ctx_new(0);
        size_t size = 0;
        if (spng_set_png_buffer(ctx, bytes.data(), bytes.size()) != 0 ||
            spng_decoded_image_size(ctx, SPNG_FMT_RGB8, &size) != 0) {
          size = 0;
        }
        pixels.resize(size);
        if (size == 0 || spng_decode_image(ctx, pixels.data(), size, SPNG_FMT_RGB8, 0) != 0) {
          pixels.clear();
        }
        spng_ctx_free(ctx);
      },
      20);
  char text[64];
  std::snprintf(text, sizeof(text), "%.3f (%s)", ms,
                pixels == expected.data ? "same pixels" : "DIFFERENT pixels");
  return text;
}
#else
const char* kSpngNote = "";
std::string SpngColumn(const std::string& /*path*/, const patlab::camera::Image& /*expected*/) {
  return "(not built)";
}
#endif

// Decoded pixels -> detections (stages 2-6, as patlab detect runs them per frame) on the real SSL
// 2008 frame with the settings of tests/data/vision, RGB and UYVY, beside OpenCV's stages 2-4
// alone on the same frame and classes; then the decode time of each shared frame file.
void RealFrames(const std::string& dir) {
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  VisionPipeline pipeline(patlab::formats::LoadThresholds(data + "ssl-2008.thresholds.toml"),
                          patlab::formats::LoadCalibration(data + "ssl-2008.calibration.toml"),
                          SegmenterOptions{});
  detect::Detector detector(formats::LoadDetectorSettings(data + "ssl-2008.detector.toml"));
  std::vector<int> palette_label;
  for (const ColorClass& c : pipeline.thresholds().classes) {
    palette_label.push_back(detector.ColourLabel(c.name));
  }
  const patlab::camera::Image rgb = ReadFrame(dir + "/ssl-field-2008.jpg");
  std::vector<detect::Blob> blobs, palette_blobs;
  std::vector<detect::Detection> detections;
  std::printf(
      "\nssl-field-2008.jpg 780x580, %zu classes: decoded pixels -> detections (stages 2-6), one "
      "core, CPU ms: median of 200 (fastest run)\n%-6s %20s %28s %8s %11s\n",
      pipeline.thresholds().classes.size(), "pixels", "patlab", "OpenCV (stages 2-4 only)", "ratio",
      "detections");
  for (const patlab::camera::Image& frame : {rgb, patlab::camera::ToUyvy(rgb)}) {
    const double ours = MedianMs(
        [&] {
          pipeline.Process(frame, &blobs);
          palette_blobs.clear();
          for (const detect::Blob& b : blobs) {
            const int label = palette_label[static_cast<size_t>(b.colour)];
            if (label >= 0) palette_blobs.push_back(detect::Blob{b.position_mm, label, b.area_mm2});
          }
          detector.Detect(palette_blobs, &detections);
        },
        200);
    const double ours_min = last_min_ms;
    const double cv_ms = OpenCvMs(frame, pipeline.thresholds());
    const double cv_min = last_min_ms;
    std::printf("%-6s %11.3f (%6.3f) %19.3f (%6.3f) %7.1fx %11zu\n",
                frame.format == patlab::camera::PixelFormat::kUyvy ? "UYVY" : "RGB", ours, ours_min,
                cv_ms, cv_min, cv_ms / ours, detections.size());
  }
  std::printf(
      "\ndecode: patlab::vision::ReadFrame (file read + libjpeg-turbo / libpng)%s, CPU ms, median "
      "of 20, one core\n%-38s %11s %12s %12s\n",
      kSpngNote, "file", "size", "ReadFrame", "libspng");
  for (const char* name :
       {"ssl-field-2008.jpg", "vss-test-frame.png", "ssl-standard-pattern-2010-16ids.png"}) {
    patlab::camera::Image image;
    const std::string path = dir + "/" + name;
    const double ms = MedianMs([&] { image = ReadFrame(path); }, 20);
    char size[32];
    std::snprintf(size, sizeof(size), "%dx%d", image.width_px, image.height_px);
    std::printf("%-38s %11s %12.3f %12s\n", name, size, ms, SpngColumn(path, image).c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one core, like ours
  const Thresholds thresholds =
      patlab::formats::ParseCmvisionColors(kColors, "ssl-2008.colors.txt");
  std::vector<std::pair<std::string, patlab::camera::Image>> frames;
  frames.emplace_back("synthetic 640x480", SyntheticField(640, 480));
  frames.emplace_back("synthetic 780x580", SyntheticField(780, 580));
  const std::string dir = argc > 1 ? argv[1] : std::string(PATLAB_SOURCE_DIR) + "/../shared/frames";
  if (std::filesystem::exists(dir + "/ssl-field-2008.jpg")) {
    frames.emplace_back("ssl-field-2008.jpg 780x580", ReadFrame(dir + "/ssl-field-2008.jpg"));
    // The same real frame cropped to 640x480.
    patlab::camera::Image crop = patlab::camera::Image::Rgb(640, 480);
    const patlab::camera::Image& full = frames.back().second;
    for (int y = 0; y < 480; ++y) std::copy_n(full.Row(y + 50), 640 * 3, crop.Row(y));
    frames.emplace_back("ssl-field-2008.jpg crop 640x480", crop);
  }
  std::printf(
      "stages 2-4 (classify, runs + union-find, regions), %zu YUV classes, RGB frames, one core,\n"
      "CPU time of this thread, median of 200 (ours) / 50 (OpenCV %s) runs\n\n",
      thresholds.classes.size(), CV_VERSION);
  std::printf("%-34s %12s %12s %8s %10s %10s\n", "frame", "ours ms", "OpenCV ms", "ratio",
              "regions", "cv regions");
  for (const auto& [name, frame] : frames) {
    const Result r = Compare(frame, thresholds);
    std::printf("%-34s %12.3f %12.3f %7.1fx %10ld %10ld\n", name.c_str(), r.ours_ms, r.opencv_ms,
                r.opencv_ms / r.ours_ms, r.ours_regions, r.opencv_regions);
  }
  // Also from camera-native UYVY (no colour conversion needed).
  const patlab::camera::Image uyvy = patlab::camera::ToUyvy(frames[1].second);
  Segmenter segmenter(thresholds, SegmenterOptions{1, 0.0});
  std::printf("\nours on UYVY 780x580 (camera-native, no conversion): %.3f ms\n",
              MedianMs([&] { segmenter.Process(uyvy); }, 200));
  if (std::filesystem::exists(dir + "/ssl-field-2008.jpg")) RealFrames(dir);
  return 0;
}

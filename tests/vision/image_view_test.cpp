// camera::ImageView: the pipeline reads a frame where it is, with any strides. The same pixels in
// any layout -- packed, BGR bytes read backwards, the RGB of an RGBA buffer, column-major
// (numpy's Fortran order), upside down, a crop of a wider buffer, UYVY rows with padding -- give
// the class image, runs, regions and detections of the packed Image, byte for byte.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_results.h"
#include "patlab/vision/segment.h"

namespace patlab::vision {
namespace {

// The pixels of `image` copied into `buffer` in another layout, and the view that reads them
// there: pixel (x, y) channel c at origin + y * row + x * pixel + c * channel (strides in bytes).
struct Layout {
  const char* name;
  std::ptrdiff_t row, pixel, channel;
  size_t bytes;
  std::ptrdiff_t origin;
};

std::vector<Layout> Layouts(int w, int h) {
  const std::ptrdiff_t W = w, H = h;
  return {{"packed", 3 * W, 3, 1, size_t(3 * W * H), 0},
          {"bgr read backwards", 3 * W, 3, -1, size_t(3 * W * H), 2},
          {"rgb of rgba", 4 * W, 4, 1, size_t(4 * W * H), 0},
          {"column-major", 1, H, H * W, size_t(3 * W * H), 0},
          {"upside down", -3 * W, 3, 1, size_t(3 * W * H), 3 * W * (H - 1)},
          {"crop of a wider buffer", 3 * (W + 7) + 5, 3, 1, size_t((3 * (W + 7) + 5) * (H + 2)),
           3 * (W + 7) + 5 + 9}};
}

camera::ImageView Place(const camera::Image& image, const Layout& l, std::vector<uint8_t>* buffer) {
  buffer->assign(l.bytes, 0xAB);
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      for (int c = 0; c < 3; ++c) {
        (*buffer)[static_cast<size_t>(l.origin + y * l.row + x * l.pixel + c * l.channel)] =
            image.Row(y)[3 * x + c];
      }
    }
  }
  camera::ImageView view;
  view.data = buffer->data() + l.origin;
  view.width_px = image.width_px;
  view.height_px = image.height_px;
  view.row_stride = l.row;
  view.pixel_stride = l.pixel;
  view.channel_stride = l.channel;
  return view;
}

void ExpectSameSegmentation(const Segmenter& a, const Segmenter& b, const char* what) {
  EXPECT_EQ(a.class_image(), b.class_image()) << what;
  ASSERT_EQ(a.runs().size(), b.runs().size()) << what;
  ASSERT_EQ(a.regions().size(), b.regions().size()) << what;
  for (size_t i = 0; i < a.regions().size(); ++i) {
    EXPECT_EQ(a.regions()[i].area_px, b.regions()[i].area_px) << what;
    EXPECT_EQ(a.regions()[i].centroid_px, b.regions()[i].centroid_px) << what;
  }
}

TEST(ImageView, AnImageIsItsPackedView) {
  const camera::Image image = camera::Image::Rgb(5, 4);
  const camera::ImageView view = image;
  EXPECT_EQ(view.data, image.data.data());
  EXPECT_EQ(view.row_stride, 15);
  EXPECT_EQ(view.pixel_stride, 3);
  EXPECT_EQ(view.channel_stride, 1);
  EXPECT_TRUE(view.PackedPixels());
}

// Random pixels (every class boundary everywhere) through YUV thresholds (the real frames', 7
// classes) and RGB ones: every layout classifies as the packed Image, and ToRgb of the view is
// the Image.
TEST(ImageView, EveryLayoutSegmentsAsThePackedImage) {
  const int w = 131, h = 57;  // no multiple of a vector width
  camera::Image image = camera::Image::Rgb(w, h);
  std::mt19937 rng(9);
  for (uint8_t& v : image.data) v = static_cast<uint8_t>(rng() % 4 == 0 ? 20 : rng());
  for (const char* file : {"ssl-2008.thresholds.toml", "ssl-standard-sheet.thresholds.toml"}) {
    const Thresholds t =
        formats::LoadThresholds(std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/" + file);
    SegmenterOptions o;
    o.min_area_px = 1;
    Segmenter packed(t, o), strided(t, o);
    packed.Process(image);
    for (const Layout& l : Layouts(w, h)) {
      std::vector<uint8_t> buffer;
      const camera::ImageView view = Place(image, l, &buffer);
      EXPECT_EQ(view.PackedPixels(), l.pixel == 3 && l.channel == 1) << l.name;
      strided.Process(view);
      ExpectSameSegmentation(packed, strided, l.name);
      EXPECT_EQ(camera::ToRgb(view).data, image.data) << l.name;
    }
  }
}

// UYVY frames with padded rows (a camera's stride): the packed UYVY Image's classes.
TEST(ImageView, UyvyRowsWithPaddingSegmentAsThePackedImage) {
  camera::Image rgb = camera::Image::Rgb(64, 20);
  std::mt19937 rng(4);
  for (uint8_t& v : rgb.data) v = static_cast<uint8_t>(rng());
  const camera::Image uyvy = camera::ToUyvy(rgb);
  std::vector<uint8_t> buffer(static_cast<size_t>(uyvy.height_px) * (uyvy.RowBytes() + 32));
  for (int y = 0; y < uyvy.height_px; ++y) {
    std::memcpy(buffer.data() + static_cast<size_t>(y) * (uyvy.RowBytes() + 32), uyvy.Row(y),
                static_cast<size_t>(uyvy.RowBytes()));
  }
  camera::ImageView view = uyvy;
  view.data = buffer.data();
  view.row_stride = uyvy.RowBytes() + 32;
  const Thresholds t = formats::LoadThresholds(std::string(PATLAB_SOURCE_DIR) +
                                               "/tests/data/vision/ssl-2008.thresholds.toml");
  Segmenter packed(t, SegmenterOptions{}), padded(t, SegmenterOptions{});
  packed.Process(uyvy);
  padded.Process(view);
  ExpectSameSegmentation(packed, padded, "uyvy");
  EXPECT_EQ(camera::ToRgb(view).data, camera::ToRgb(uyvy).data);
}

// The golden frame through FrameDetector from every layout: the CSV of the packed frame.
TEST(ImageView, FrameDetectorFindsTheSameRobotsInEveryLayout) {
  const std::string golden = std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/ssl-frame";
  const camera::Image image = camera::ToRgb(ReadFrame(golden + ".png"));
  FrameDetectorOptions options;
  ApplyFrameSettings(formats::LoadFrameSettings(golden + ".detector.toml"), &options);
  FrameDetector frames(formats::LoadThresholds(golden + ".thresholds.toml"),
                       formats::LoadCalibration(golden + ".calibration.toml"),
                       formats::LoadDetectorSettings(golden + ".detector.toml"), options);
  const auto csv = [&frames](const camera::ImageView& view) {
    FrameResultsWriter writer(frames, false);
    writer.Add(frames.Detect(view, "frame"));
    return writer.Csv();
  };
  const std::string expected = csv(image);
  ASSERT_GT(frames.Detect(image, "frame").detections.size(), 0u);
  for (const Layout& l : Layouts(image.width_px, image.height_px)) {
    std::vector<uint8_t> buffer;
    EXPECT_EQ(csv(Place(image, l, &buffer)), expected) << l.name;
  }
}

}  // namespace
}  // namespace patlab::vision

// docs/architecture.md rule 7 for the real-frame loop: once a pipeline has seen a frame of a size
// (its buffers have grown, the RGB cell table is built), stages 2-5 -- and stage 6 with the blobs
// matched to the detector palette, FrameDetector as patlab detect runs it -- do not allocate.
// Global operator new is counted (this replaces it for the whole test_vision binary; it only
// counts).
#include <gtest/gtest.h>

#include <filesystem>

#include "../allocation_counter.h"
#include "../frame_test_util.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/pipeline.h"

namespace patlab::vision {
namespace {

// Stages 2-5 on a rendered 780x580 RGB frame with YUV thresholds (the 64^3 cell table and the
// exact BT.601 path for mixed cells) and a distorted pinhole camera, and on the same frame as
// UYVY (the camera-native path).
TEST(VisionAllocation, WarmPipelineDoesNotAllocate) {
  const camera::Calibration cal = formats::ParseCalibration(
      "model = \"pinhole\"\nimage_size_px = [780, 580]\n[pinhole]\nfx_px = 850\nfy_px = 850\n"
      "cx_px = 390\ncy_px = 290\nk1 = -0.2\ncamera_position_mm = [0, 0, 4000]\nyaw_deg = 0\n"
      "[heights]\ndefault_mm = 140\n",
      "c.toml");
  const Thresholds thresholds = formats::ParseThresholdsToml(
      "[[class]]\nname = \"blue\"\nu = [150, 255]\nv = [0, 125]\n"
      "[[class]]\nname = \"pink\"\ny = [100, 255]\nv = [170, 255]\n"
      "[[class]]\nname = \"green\"\ny = [70, 255]\nu = [0, 120]\nv = [0, 110]\n",
      "t.toml");
  std::vector<render::Disc> discs;
  for (int i = 0; i < 10; ++i) {
    const Vec2 c(-1500.0 + 330.0 * i, 200.0 * (i % 3) - 200.0);
    discs.push_back({c, 25, {20, 40, 230}});
    discs.push_back({c + Vec2(35, 54.8), 20, {250, 60, 200}});
    discs.push_back({c + Vec2(-54.8, -35), 20, {40, 220, 60}});
  }
  const camera::Image rgb =
      render::RenderWorldDiscs(780, 580, cal.camera, 140, {40, 70, 30}, discs);
  const camera::Image uyvy = camera::ToUyvy(rgb);
  for (const camera::Image* image : {&rgb, &uyvy}) {
    VisionPipeline pipeline(thresholds, cal, SegmenterOptions{});
    std::vector<detect::Blob> blobs;
    VisionStats stats;
    const long start = patlab::testing::AllocationCount();
    pipeline.Process(*image, &blobs, &stats);  // grows the buffers, builds the cell table
    EXPECT_GT(patlab::testing::AllocationCount() - start, 0);  // the counter sees allocations
    ASSERT_EQ(blobs.size(), 30u);
    const long before = patlab::testing::AllocationCount();
    pipeline.Process(*image, &blobs, &stats);
    EXPECT_EQ(patlab::testing::AllocationCount() - before, 0);
    EXPECT_EQ(blobs.size(), 30u);
  }
}

// Stages 2-6 on the real SSL 2008 frame, as patlab detect runs them per frame (FrameDetector),
// with and without timing, and with the frame scaled to a light 30% brighter than its own (setup's
// [frame] light_luma): the scaled copy reuses its buffer.
TEST(VisionAllocation, WarmRealFrameLoopDoesNotAllocate) {
  if (!std::filesystem::exists(testing::SharedFrames()))
    GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  const camera::Image image = ReadFrame(testing::SharedFrames() + "/ssl-field-2008.jpg");
  for (const auto& [timing, scaled] : {std::pair(false, false), {true, false}, {false, true}}) {
    FrameDetectorOptions options;
    options.collect_timing = timing;
    if (scaled) options.light_luma = 1.3 * FrameLight(image);
    FrameDetector frames(formats::LoadThresholds(data + "ssl-2008.thresholds.toml"),
                         formats::LoadCalibration(data + "ssl-2008.calibration.toml"),
                         formats::LoadDetectorSettings(data + "ssl-2008.detector.toml"), options);
    const std::string name = "ssl-field-2008.jpg";
    const size_t found = frames.Detect(image, name).detections.size();
    if (!scaled) {
      ASSERT_EQ(found, 5u);
    }
    const long before = patlab::testing::AllocationCount();
    const FrameResult& result = frames.Detect(image, name);
    EXPECT_EQ(patlab::testing::AllocationCount() - before, 0)
        << "timing " << timing << ", scaled " << scaled;
    EXPECT_EQ(result.detections.size(), found);
  }
}

}  // namespace
}  // namespace patlab::vision

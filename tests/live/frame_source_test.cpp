// Frame sources (live/frame_source.h): a frame list read in order and looped, a lossless video
// written with FFmpeg's libraries read back pixel for pixel with its presentation times, the
// kinds of SOURCE arguments, and sources that cannot be opened.
#include "patlab/live/frame_source.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/vision/frame_io.h"
#include "video_writer.h"

namespace patlab::live {
namespace {

const std::string kGoldenPng = std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/ssl-frame.png";

// Three frames that differ: the golden frame with a pixel row set to 0, 1, 2.
std::vector<camera::Image> ThreeFrames() {
  std::vector<camera::Image> frames;
  for (int i = 0; i < 3; ++i) {
    camera::Image image = vision::ReadFrame(kGoldenPng);
    std::fill(image.data.begin(), image.data.begin() + image.RowBytes(), static_cast<uint8_t>(i));
    frames.push_back(std::move(image));
  }
  return frames;
}

camera::Image Copy(const SourceFrame& frame) {
  camera::Image image;
  CopyToImage(frame, &image);
  return image;
}

TEST(FrameSource, KindsOfSources) {
  EXPECT_EQ(KindOfSource("/dev/video0"), SourceKind::kDevice);
  EXPECT_EQ(KindOfSource("v4l2:/dev/video2"), SourceKind::kDevice);
  EXPECT_EQ(KindOfSource("match.MP4"), SourceKind::kVideo);
  EXPECT_EQ(KindOfSource("a.mkv"), SourceKind::kVideo);
  EXPECT_EQ(KindOfSource("frames/"), SourceKind::kFrames);
  EXPECT_EQ(KindOfSource("frame.png"), SourceKind::kFrames);
  EXPECT_EQ(KindOfSource("list.txt"), SourceKind::kFrames);
}

TEST(FrameSource, FrameListInOrderThenLooped) {
  patlab::testing::TempDir dir;
  const std::vector<camera::Image> frames = ThreeFrames();
  // Names appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "f" + ...
  for (size_t i = 0; i < 3; ++i) {
    std::string name = "f";
    name += std::to_string(i);
    name += ".png";
    vision::WritePng(frames[i], dir.Path(name));
  }
  FrameSourceOptions options;
  options.loop = true;
  options.list_rate_hz = 10.0;
  std::unique_ptr<FrameSource> source = OpenFrameSource(dir.Path(), options);
  SourceFrame frame;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(source->Next(&frame));
    EXPECT_EQ(frame.index, i);
    EXPECT_DOUBLE_EQ(frame.media_time_s, i / 10.0);
    EXPECT_EQ(frame.stride_bytes, frames[0].RowBytes());
    EXPECT_EQ(Copy(frame).data, frames[static_cast<size_t>(i % 3)].data);
  }
  options.loop = false;
  source = OpenFrameSource(dir.Path(), options);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(source->Next(&frame));
  EXPECT_FALSE(source->Next(&frame));
}

TEST(FrameSource, VideoReadsBackTheFramesWritten) {
  patlab::testing::TempDir dir;
  const std::vector<camera::Image> frames = ThreeFrames();
  const std::string path = dir.Path("clip.mkv");
  ASSERT_TRUE(testing::WriteLosslessVideo(path, frames, 25));
  std::unique_ptr<FrameSource> source = OpenFrameSource(path, {});
  SourceFrame frame;
  double first_capture_s = 0.0;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(source->Next(&frame));
    EXPECT_EQ(frame.index, i);
    EXPECT_EQ(frame.width_px, frames[0].width_px);
    EXPECT_EQ(frame.height_px, frames[0].height_px);
    EXPECT_EQ(frame.format, camera::PixelFormat::kRgb8);
    EXPECT_NEAR(frame.media_time_s, i / 25.0, 1e-3);  // Matroska keeps milliseconds
    if (i == 0) first_capture_s = frame.capture_time_s;
    EXPECT_NEAR(frame.capture_time_s - first_capture_s, frame.media_time_s, 1e-6);  // epoch doubles
    EXPECT_EQ(Copy(frame).data, frames[static_cast<size_t>(i)].data) << "frame " << i;
  }
  EXPECT_FALSE(source->Next(&frame));
}

TEST(FrameSource, SourcesThatCannotBeOpened) {
  patlab::testing::TempDir dir;
  const std::string not_video = dir.Write("noise.mp4", "this is no video");
  EXPECT_THROW(OpenFrameSource(not_video, {}), InputError);
  EXPECT_THROW(OpenFrameSource(dir.Path("missing.mkv"), {}), InputError);
  EXPECT_THROW(OpenFrameSource(dir.Path("missing.png"), {}), InputError);
  EXPECT_THROW(OpenFrameSource("/dev/patlab-no-such-camera", {}), InputError);
  FrameSourceOptions options;
  options.list_rate_hz = 0.0;
  EXPECT_INPUT_ERROR(OpenFrameSource(kGoldenPng, options),
                     "--list-rate is 0; expected > 0 frames per second");
}

}  // namespace
}  // namespace patlab::live

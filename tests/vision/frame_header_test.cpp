// A frame's size read from its header before any pixel is decoded (frame_io.h,
// ReadFrameHeaderSize), against the sizes `file` reports for the same files and the decoders'.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "../frame_test_util.h"
#include "../test_util.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {
namespace {

using testing::ScratchDir;
using testing::WriteBytes;
using testing::WriteText;

using patlab::testing::kSource;

std::pair<int, int> SizeOf(const std::string& path, int raw_w = 0, int raw_h = 0) {
  const std::optional<FrameHeaderSize> size = ReadFrameHeaderSize(path, raw_w, raw_h);
  EXPECT_TRUE(size.has_value()) << path;
  return size ? std::pair{size->width_px, size->height_px} : std::pair{-1, -1};
}

std::vector<uint8_t> Bytes(const std::string& path) { return ReadFileBytes(path); }

// The sizes `file` prints for these files (PNG, baseline JPEG, PPM with a comment), and the
// decoders' sizes of the same files.
TEST(FrameHeader, ReadsTheSizeOfEachFormatAsTheDecoderDoes) {
  const std::vector<std::pair<std::string, std::pair<int, int>>> frames = {
      {kSource + "/tests/data/golden/ssl-frame.png", {640, 480}},
      {kSource + "/tests/fuzz/corpus/image/python.jpg", {16, 16}},
      {kSource + "/tests/fuzz/corpus/image/tiny.ppm", {8, 6}},
  };
  for (const auto& [path, size] : frames) {
    EXPECT_EQ(SizeOf(path), size) << path;
    const camera::Image decoded = ReadFrame(path);
    EXPECT_EQ(SizeOf(path), (std::pair{decoded.width_px, decoded.height_px})) << path;
  }
}

TEST(FrameHeader, ReadsTheSharedRealFrames) {
  const std::string dir = testing::SharedFrames();
  if (!std::filesystem::exists(dir + "/ssl-field-2008.jpg")) GTEST_SKIP() << "no " << dir;
  EXPECT_EQ(SizeOf(dir + "/ssl-field-2008.jpg"), (std::pair{780, 580}));
  EXPECT_EQ(SizeOf(dir + "/vss-test-frame.png"), (std::pair{765, 613}));
}

// A JPEG's SOF behind a large APP1 segment (EXIF) and fill bytes is still found.
TEST(FrameHeader, FindsTheJpegFrameBehindApplicationSegments) {
  const std::string dir = ScratchDir();
  std::vector<uint8_t> jpeg = Bytes(kSource + "/tests/fuzz/corpus/image/python.jpg");
  std::vector<uint8_t> app1 = {0xff, 0xff, 0xe1, 0xea, 0x62};  // a fill byte, APP1 of 60002
  app1.resize(app1.size() + 60000, 0);
  jpeg.insert(jpeg.begin() + 2, app1.begin(), app1.end());
  WriteBytes(dir + "/big-exif.jpg", jpeg);
  EXPECT_EQ(SizeOf(dir + "/big-exif.jpg"), (std::pair{16, 16}));
  const camera::Image decoded = ReadFrame(dir + "/big-exif.jpg");  // still a valid JPEG
  EXPECT_EQ(decoded.width_px, 16);
}

TEST(FrameHeader, ARawFrameHasTheGivenSizeAndNoHeader) {
  const std::string dir = ScratchDir();
  WriteText(dir + "/f.yuv", "abcd");  // the size is not read from the file
  EXPECT_EQ(SizeOf(dir + "/f.yuv", 640, 482), (std::pair{640, 482}));
  EXPECT_FALSE(ReadFrameHeaderSize(dir + "/f.yuv", 0, 0).has_value());
}

// No size where the header cannot give one: the decoder then says what is wrong.
TEST(FrameHeader, NoSizeFromADamagedHeaderOrAnotherFile) {
  const std::string dir = ScratchDir();
  std::vector<uint8_t> png = Bytes(kSource + "/tests/data/golden/ssl-frame.png");
  png[12] = 'X';  // the first chunk is no longer IHDR
  WriteBytes(dir + "/f.png", png);
  WriteBytes(dir + "/sos.jpg", {0xff, 0xd8, 0xff, 0xda, 0x00, 0x02, 0xff, 0xd9});
  WriteText(dir + "/text.png", "this is text, not an image\n");
  WriteText(dir + "/bad.ppm", "P6\nfour 4\n255\n");
  for (const char* name : {"f.png", "sos.jpg", "text.png", "bad.ppm", "missing.png"}) {
    EXPECT_FALSE(ReadFrameHeaderSize(dir + "/" + std::string(name), 0, 0).has_value()) << name;
  }
}

TEST(FrameHeader, ASizeBeyondThePixelBudgetIsRefusedFromTheHeader) {
  const std::string dir = ScratchDir();
  WriteText(dir + "/f.ppm", "P6\n20000 20000\n255\nabc");
  EXPECT_INPUT_ERROR(ReadFrameHeaderSize(dir + "/f.ppm", 0, 0),
                     dir + "/f.ppm: image size 20000x20000; expected 1 to 268435456 pixels");
  WriteText(dir + "/z.ppm", "P6\n0 2\n255\n");
  EXPECT_INPUT_ERROR(ReadFrameHeaderSize(dir + "/z.ppm", 0, 0),
                     dir + "/z.ppm: image size 0x2; expected 1 to 268435456 pixels");
}

}  // namespace
}  // namespace patlab::vision

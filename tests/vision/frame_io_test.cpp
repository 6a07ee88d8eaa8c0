#include "patlab/vision/frame_io.h"

#include <gtest/gtest.h>
#include <jpeglib.h>

#include <cstdio>
#include <filesystem>

#include "../frame_test_util.h"

namespace patlab::vision {
namespace {

using testing::ScratchDir;
using testing::WriteBytes;

camera::Image Gradient(int w, int h) {
  camera::Image image = camera::Image::Rgb(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = image.Row(y) + 3 * x;
      p[0] = static_cast<uint8_t>(x * 7);
      p[1] = static_cast<uint8_t>(y * 11);
      p[2] = static_cast<uint8_t>((x + y) * 3);
    }
  }
  return image;
}

std::vector<uint8_t> EncodeJpegForTest(const camera::Image& image) {
  jpeg_compress_struct cinfo;
  jpeg_error_mgr jerr;
  cinfo.err = jpeg_std_error(&jerr);
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = static_cast<JDIMENSION>(image.width_px);
  cinfo.image_height = static_cast<JDIMENSION>(image.height_px);
  cinfo.input_components = 3;
  cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 95, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<uint8_t*>(image.Row(static_cast<int>(cinfo.next_scanline)));
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  std::vector<uint8_t> out(buffer, buffer + size);
  jpeg_destroy_compress(&cinfo);
  std::free(buffer);
  return out;
}

TEST(FrameIo, PngRoundTripIsExact) {
  const std::string dir = ScratchDir();
  const camera::Image image = Gradient(37, 23);
  WritePng(image, dir + "/a.png");
  const camera::Image back = ReadFrame(dir + "/a.png");
  EXPECT_EQ(back.width_px, 37);
  EXPECT_EQ(back.height_px, 23);
  EXPECT_EQ(back.format, camera::PixelFormat::kRgb8);
  EXPECT_EQ(back.data, image.data);
}

TEST(FrameIo, PpmRoundTripIsExact) {
  const std::string dir = ScratchDir();
  const camera::Image image = Gradient(5, 4);
  WritePpm(image, dir + "/a.ppm");
  EXPECT_EQ(ReadFrame(dir + "/a.ppm").data, image.data);
}

TEST(FrameIo, PpmWithCommentsInHeader) {
  std::string header = "P6\n# made by hand\n2 1\n# another\n255\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  for (uint8_t v : {1, 2, 3, 4, 5, 6}) bytes.push_back(v);
  const camera::Image image = DecodePpm(bytes, "x.ppm");
  EXPECT_EQ(image.width_px, 2);
  EXPECT_EQ(image.data, (std::vector<uint8_t>{1, 2, 3, 4, 5, 6}));
}

TEST(FrameIo, JpegDecodesCloseToOriginal) {
  camera::Image image = camera::Image::Rgb(64, 48);  // smooth, so JPEG keeps it to a few levels
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      uint8_t* p = image.Row(y) + 3 * x;
      p[0] = static_cast<uint8_t>(3 * x);
      p[1] = static_cast<uint8_t>(4 * y);
      p[2] = static_cast<uint8_t>(100 + x + y);
    }
  }
  const camera::Image back = DecodeJpeg(EncodeJpegForTest(image), "a.jpg");
  ASSERT_EQ(back.width_px, 64);
  ASSERT_EQ(back.height_px, 48);
  double error = 0;
  for (size_t i = 0; i < image.data.size(); ++i) error += std::abs(image.data[i] - back.data[i]);
  EXPECT_LT(error / static_cast<double>(image.data.size()), 6.0);  // quality 95: a few levels
}

TEST(FrameIo, TruncatedPngNamesTheByteOffset) {
  std::vector<uint8_t> bytes = EncodePng(Gradient(16, 16));
  // Signature (8) + IHDR (25) = 33; the next chunk starts at byte 33. Cut 10 bytes into it.
  bytes.resize(43);
  const std::string type(bytes.begin() + 37, bytes.begin() + 41);
  EXPECT_INPUT_ERROR(
      DecodePng(bytes, "t.png"),
      "t.png: byte 43: truncated PNG: chunk '" + type + "' at byte 33 needs " +
          std::to_string(12 + (bytes[33] << 24 | bytes[34] << 16 | bytes[35] << 8 | bytes[36])) +
          " bytes but the file ends after 10; expected a complete PNG file");
}

TEST(FrameIo, PngWithoutIendIsTruncated) {
  std::vector<uint8_t> bytes = EncodePng(Gradient(16, 16));
  bytes.resize(bytes.size() - 12);  // drop IEND
  EXPECT_INPUT_ERROR(DecodePng(bytes, "t.png"),
                     "t.png: byte " + std::to_string(bytes.size()) +
                         ": truncated PNG: the file ends inside a chunk header; expected a "
                         "complete PNG file ending in an IEND chunk");
}

TEST(FrameIo, CorruptPngDataIsReported) {
  std::vector<uint8_t> bytes = EncodePng(Gradient(16, 16));
  // Find the IDAT chunk and damage its data: the CRC no longer matches.
  size_t offset = 8;
  while (std::string(bytes.begin() + static_cast<long>(offset) + 4,
                     bytes.begin() + static_cast<long>(offset) + 8) != "IDAT") {
    offset += 12 + (bytes[offset] << 24 | bytes[offset + 1] << 16 | bytes[offset + 2] << 8 |
                    bytes[offset + 3]);
  }
  bytes[offset + 10] ^= 0xff;
  // The rest is libpng's own wording.
  EXPECT_INPUT_ERROR_STARTS_WITH(DecodePng(bytes, "c.png"), "c.png: corrupt PNG (libpng: ");
}

TEST(FrameIo, TruncatedJpegNamesTheByteOffset) {
  std::vector<uint8_t> bytes = EncodeJpegForTest(Gradient(64, 48));
  bytes.resize(bytes.size() / 2);
  EXPECT_INPUT_ERROR(DecodeJpeg(bytes, "t.jpg"),
                     "t.jpg: byte " + std::to_string(bytes.size()) +
                         ": corrupt or truncated JPEG (libjpeg: Premature end of JPEG file); "
                         "expected a complete JPEG image");
}

TEST(FrameIo, TruncatedPpm) {
  const std::string header = "P6\n4 2\n255\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  bytes.resize(bytes.size() + 20);
  EXPECT_INPUT_ERROR(DecodePpm(bytes, "t.ppm"),
                     "t.ppm: byte 31: truncated PPM: 4x2 needs 24 bytes of pixels from byte 11; "
                     "expected a file of 35 bytes");
}

TEST(FrameIo, PpmWith16BitSamplesIsRefused) {
  const std::string text = "P6 4 2 65535\n";
  EXPECT_INPUT_ERROR(DecodePpm(std::vector<uint8_t>(text.begin(), text.end()), "d.ppm"),
                     "d.ppm: byte 7: PPM maxval 65535; expected 255 (8 bits per sample)");
}

TEST(FrameIo, PpmHeaderWithoutHeight) {
  const std::string text = "P6 4 x";
  EXPECT_INPUT_ERROR(DecodePpm(std::vector<uint8_t>(text.begin(), text.end()), "h.ppm"),
                     "h.ppm: byte 5: bad PPM header: unexpected character; expected the height "
                     "(a decimal number)");
}

TEST(FrameIo, UnknownFormat) {
  const std::string dir = ScratchDir();
  WriteBytes(dir + "/x.png", {'h', 'e', 'l', 'l', 'o'});
  EXPECT_INPUT_ERROR(ReadFrame(dir + "/x.png"),
                     dir +
                         "/x.png: byte 0: unknown image format; expected a PNG, JPEG or binary "
                         "PPM (P6) file");
}

TEST(FrameIo, RawUyvyOfTheWrongSize) {
  const std::string dir = ScratchDir();
  WriteBytes(dir + "/f.yuv", std::vector<uint8_t>(1000, 128));
  EXPECT_INPUT_ERROR(ReadRawUyvy(dir + "/f.yuv", 20, 30),
                     dir +
                         "/f.yuv: 1000 bytes; expected 1200 bytes for a 20x30 UYVY frame "
                         "(width x height x 2)");
  EXPECT_INPUT_ERROR(ReadRawUyvy(dir + "/f.yuv", 25, 20),
                     dir +
                         "/f.yuv: raw frame size 25x20; expected a positive even width and a "
                         "positive height");
  const camera::Image image = ReadRawUyvy(dir + "/f.yuv", 20, 25);
  EXPECT_EQ(image.format, camera::PixelFormat::kUyvy);
  EXPECT_EQ(image.RowBytes(), 40);
}

TEST(FrameIo, UyvyRoundTripThroughRgbKeepsGreys) {
  camera::Image grey = camera::Image::Rgb(4, 1);
  for (int i = 0; i < 12; ++i)
    grey.data[static_cast<size_t>(i)] = static_cast<uint8_t>(40 + 50 * (i / 3));
  const camera::Image yuv = camera::ToUyvy(grey);
  EXPECT_EQ(yuv.data[0], 128);  // U of a grey pixel pair
  EXPECT_EQ(yuv.data[2], 128);  // V
  EXPECT_EQ(camera::ToRgb(yuv).data, grey.data);
}

TEST(FrameIo, ExpandFrameListSortsDirectoriesAndReadsLists) {
  const std::string dir = ScratchDir();
  for (const char* name : {"b.png", "a.jpg", "c.txt", "d.ppm"}) WriteBytes(dir + "/" + name, {0});
  std::filesystem::create_directory(dir + "/frames");
  for (const char* name : {"2.png", "10.png", "notes.md"}) WriteBytes(dir + "/frames/" + name, {0});
  testing::WriteText(dir + "/list.txt", "# frames\nb.png\n  d.ppm  # trailing comment\n\n");
  const auto frames = ExpandFrameList({dir + "/frames", dir + "/list.txt", dir + "/a.jpg"});
  EXPECT_EQ(frames, (std::vector<std::string>{dir + "/frames/10.png", dir + "/frames/2.png",
                                              dir + "/b.png", dir + "/d.ppm", dir + "/a.jpg"}));
  EXPECT_INPUT_ERROR(ExpandFrameList({dir + "/nope.png"}),
                     dir +
                         "/nope.png: no such file or directory; expected a frame, a directory "
                         "of frames or a list file");
}

TEST(FrameIo, ReadsTheSharedRealFrames) {
  const std::string frames = testing::SharedFrames();
  if (!std::filesystem::exists(frames)) GTEST_SKIP() << "no shared frames at " << frames;
  const camera::Image jpg = ReadFrame(frames + "/ssl-field-2008.jpg");
  EXPECT_EQ(jpg.width_px, 780);
  EXPECT_EQ(jpg.height_px, 580);
  const camera::Image png = ReadFrame(frames + "/vss-test-frame.png");
  EXPECT_EQ(png.width_px, 765);
  EXPECT_EQ(png.height_px, 613);
}

}  // namespace
}  // namespace patlab::vision

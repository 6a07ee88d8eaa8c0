#include "patlab/vision/color_lut.h"

#include <gtest/gtest.h>

#include "../frame_test_util.h"
#include "patlab/camera/image.h"
#include "patlab/formats/thresholds_file.h"

namespace patlab::vision {
namespace {

// CMVision's own example file layout, as distributed with the library.
constexpr const char* kCmvisionColors =
    "[Colors]\n"
    "(255,128,  0) 0.5000 2 Ball\n"
    "(255,255,  0) 0.6000 1 Yellow Team\n"
    "(  0,  0,255) 0.6000 1 Blue_Team\n"
    "\n"
    "[Thresholds]\n"
    "( 10:200, 38:120,138:200)\n"
    "(100:255,  0:110,120:160)\n"
    "( 20:140,150:255,  0:120)\n";

TEST(ColorLut, ParsesCmvisionColorsAsItIs) {
  const Thresholds t = formats::ParseCmvisionColors(kCmvisionColors, "colors.txt");
  ASSERT_EQ(t.classes.size(), 3u);
  EXPECT_EQ(t.space, ColorSpace::kYuv);
  EXPECT_EQ(t.classes[0].name, "Ball");
  EXPECT_EQ(t.classes[1].name, "Yellow Team");
  EXPECT_EQ(t.classes[0].display_rgb, (std::array<uint8_t, 3>{255, 128, 0}));
  EXPECT_DOUBLE_EQ(t.classes[1].merge, 0.6);
  EXPECT_EQ(t.classes[0].expected_num, 2);
  EXPECT_EQ(t.classes[2].range[0].lo, 20);
  EXPECT_EQ(t.classes[2].range[1].lo, 150);
  EXPECT_EQ(t.classes[2].range[2].hi, 120);
  EXPECT_EQ(t.Find("Blue_Team"), 2);
  EXPECT_EQ(t.Find("Pink"), -1);
}

TEST(ColorLut, LoadThresholdsRecognisesBothFormats) {
  const std::string dir = testing::ScratchDir();
  testing::WriteText(dir + "/colors.txt", std::string("# CMVision file\n") + kCmvisionColors);
  EXPECT_EQ(formats::LoadThresholds(dir + "/colors.txt").classes.size(), 3u);
  testing::WriteText(dir + "/t.toml",
                     "space = \"rgb\"\n[[class]]\nname = \"red\"\nr = [200, 255]\n");
  const Thresholds t = formats::LoadThresholds(dir + "/t.toml");
  EXPECT_EQ(t.space, ColorSpace::kRgb);
  EXPECT_EQ(t.classes[0].range[0].lo, 200);
  EXPECT_EQ(t.classes[0].range[1].hi, 255);  // missing channel: everything
}

// The layout CMVision users write by hand (e.g. the example file of Player's cmvision driver):
// section names in any case, padded numbers, a blank line between sections, a multi-word name.
// Written here for the test, not copied.
constexpr const char* kLowercaseSections =
    "; colour file for the lab camera\n"
    "[colors]\n"
    "(255,  0,128) 0.000000 10 Pink Dot\n"
    "(  0,255,  0) 0.500000  3 green\n"
    "\n"
    "[THRESHOLDS]\n"
    "( 25:164, 80:120,150:240)\n"
    "(  5:220, 50:120, 40:115)\n";

TEST(ColorLut, CmvisionSectionNamesAreCaseInsensitive) {
  const std::string dir = testing::ScratchDir();
  testing::WriteText(dir + "/colors.txt", kLowercaseSections);
  const Thresholds t = formats::LoadThresholds(dir + "/colors.txt");
  ASSERT_EQ(t.classes.size(), 2u);
  EXPECT_EQ(t.classes[0].name, "Pink Dot");
  EXPECT_EQ(t.classes[0].expected_num, 10);
  EXPECT_EQ(t.classes[1].display_rgb, (std::array<uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(t.classes[0].range[1].lo, 80);
  EXPECT_EQ(t.classes[1].range[0].lo, 5);
  EXPECT_EQ(t.classes[1].range[2].hi, 115);
  // A lowercase header with a bad line is reported by the CMVision parser, not by TOML's.
  testing::WriteText(dir + "/bad.txt", "[thresholds]\n(1:2, 3:4)\n");
  EXPECT_INPUT_ERROR(formats::LoadThresholds(dir + "/bad.txt"),
                     dir +
                         "/bad.txt:2: bad [Thresholds] line '(1:2, 3:4)'; expected (Ylo:Yhi, "
                         "Ulo:Uhi, Vlo:Vhi)");
}

TEST(ColorLut, CmvisionErrorsNameFileAndLine) {
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors("[Colors]\n(255,128) 0.5 2 Ball\n", "c.txt"),
                     "c.txt:2: bad [Colors] line '(255,128) 0.5 2 Ball'; expected (R,G,B) merge "
                     "expected_num Name");
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors(
                         "[Colors]\n(1,2,3) 0.5 2 A\n[Thresholds]\n(10:200, 38:120)\n", "c.txt"),
                     "c.txt:4: bad [Thresholds] line '(10:200, 38:120)'; expected (Ylo:Yhi, "
                     "Ulo:Uhi, Vlo:Vhi)");
  EXPECT_INPUT_ERROR(
      formats::ParseCmvisionColors(
          "[Colors]\n(1,2,3) 0.5 2 A\n[Thresholds]\n(10:200, 138:120, 0:255)\n", "c.txt"),
      "c.txt:4: empty U range 138:120; expected lo <= hi");
  EXPECT_INPUT_ERROR(
      formats::ParseCmvisionColors(
          "[Colors]\n(1,2,3) 0.5 2 A\n[Thresholds]\n(10:200, 0:120, 0:256)\n", "c.txt"),
      "c.txt:4: V bound 256 out of range; expected 0..255");
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors("[Colors]\n(1,2,300) 0.5 2 A\n", "c.txt"),
                     "c.txt:2: display colour component 300 out of range; expected 0..255");
  EXPECT_INPUT_ERROR(
      formats::ParseCmvisionColors(
          "[Colors]\n(1,2,3) 0.5 2 A\n(1,2,3) 0.5 2 B\n[Thresholds]\n(0:1,0:1,0:1)\n", "c.txt"),
      "c.txt:5: 2 colours but 1 thresholds; expected one [Thresholds] line per "
      "[Colors] line");
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors("[Colours]\n", "c.txt"),
                     "c.txt:1: unknown section [Colours]; expected [Colors] or [Thresholds] (any "
                     "case)");
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors("(1,2,3) 0.5 2 A\n", "c.txt"),
                     "c.txt:1: line outside a section; expected [Colors] or [Thresholds] first");
  EXPECT_INPUT_ERROR(formats::ParseCmvisionColors("\n", "c.txt"),
                     "c.txt: no colours; expected a [Colors] section with at least one line");
}

TEST(ColorLut, TomlErrorsNameFileAndLine) {
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\ny = [20, 10]\n", "t.toml"),
      "t.toml:3: empty Y range 20:10; expected lo <= hi");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\nu = [0, 999]\n", "t.toml"),
      "t.toml:3: U bound 999 out of range; expected 0..255");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\nv = 3\n", "t.toml"),
      "t.toml:3: v in [[class]] 1 is not a pair of integers; expected [lo, hi] in 0..255");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("space = \"hsv\"\n[[class]]\nname = \"a\"\n", "t.toml"),
      "t.toml:1: space is \"hsv\"; expected \"yuv\" or \"rgb\"");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\n[[class]]\nname = \"a\"\n", "t.toml"),
      "t.toml:4: duplicate class name \"a\"; expected unique names");
  EXPECT_INPUT_ERROR(formats::ParseThresholdsToml("space = \"yuv\"\n", "t.toml"),
                     "t.toml: no colour classes; expected at least one [[class]] table");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\nr = [0, 1]\n", "t.toml"),
      "t.toml:3: unknown key 'r' in [[class]] 1; expected one of: name, display, y, "
      "u, v, min_area_px, max_area_px, merge, expected_num");
  EXPECT_INPUT_ERROR(formats::ParseThresholdsToml(
                         "[[class]]\nname = \"a\"\nmin_area_px = 5\nmax_area_px = 4\n", "t.toml"),
                     "t.toml:4: max_area_px 4 in [[class]] 1; expected 0 (no limit) or "
                     "min_area_px..268435456 pixels");
  EXPECT_INPUT_ERROR(
      formats::ParseThresholdsToml("[[class]]\nname = \"a\"\nmax_area_px = -1\n", "t.toml"),
      "t.toml:3: max_area_px -1 in [[class]] 1; expected 0 (no limit) or "
      "min_area_px..268435456 pixels");
  EXPECT_INPUT_ERROR(formats::ParseThresholdsToml("[[class]\n", "t.toml"),
                     "t.toml:1: TOML syntax error: Error while parsing table header: expected "
                     "']', saw '\\n'");
}

TEST(ColorLut, FirstListedClassWinsWhereBoxesOverlap) {
  Thresholds t;
  t.space = ColorSpace::kRgb;
  ColorClass a, b;
  a.name = "a";
  a.range = {ChannelRange{100, 200}, ChannelRange{0, 255}, ChannelRange{0, 255}};
  b.name = "b";
  b.range = {ChannelRange{150, 255}, ChannelRange{0, 50}, ChannelRange{0, 255}};
  t.classes = {a, b};
  const ColorLut lut(t);
  EXPECT_EQ(lut.Classify(99, 0, 0), -1);
  EXPECT_EQ(lut.Classify(100, 0, 0), 0);   // inclusive bounds
  EXPECT_EQ(lut.Classify(175, 10, 0), 0);  // both: the first listed
  EXPECT_EQ(lut.Mask(175, 10, 0), 3u);
  EXPECT_EQ(lut.Classify(201, 10, 0), 1);
  EXPECT_EQ(lut.Classify(201, 51, 0), -1);
  EXPECT_EQ(lut.Classify(255, 50, 255), 1);
}

TEST(ColorLut, Bt601Conversion) {
  int y, u, v;
  camera::RgbToYuv(255, 255, 255, &y, &u, &v);
  EXPECT_EQ(y, 255);
  EXPECT_EQ(u, 128);
  EXPECT_EQ(v, 128);
  camera::RgbToYuv(0, 0, 255, &y, &u, &v);  // Y = 0.114 * 255 = 29; U = 128 + 0.5 * 255 -> clamped
  EXPECT_EQ(y, 29);
  EXPECT_EQ(u, 255);
  camera::RgbToYuv(255, 0, 0, &y, &u, &v);  // Y = 0.299 * 255 = 76; U = 128 - 0.169 * 255 = 85
  EXPECT_EQ(y, 77);
  EXPECT_EQ(u, 85);
  EXPECT_EQ(v, 255);
}

}  // namespace
}  // namespace patlab::vision

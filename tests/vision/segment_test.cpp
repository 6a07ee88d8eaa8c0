#include "patlab/vision/segment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../frame_test_util.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/segment_internal.h"

namespace patlab::vision {
namespace {

// Two RGB classes: red (R high, G, B low) and green (G high, R, B low).
Thresholds RedGreen() {
  Thresholds t;
  t.space = ColorSpace::kRgb;
  ColorClass red, green;
  red.name = "red";
  red.range = {ChannelRange{128, 255}, ChannelRange{0, 127}, ChannelRange{0, 127}};
  green.name = "green";
  green.range = {ChannelRange{0, 127}, ChannelRange{128, 255}, ChannelRange{0, 127}};
  t.classes = {red, green};
  return t;
}

// Draws a tiny image from text: '.' background, 'r' red, 'g' green.
camera::Image FromText(const std::vector<std::string>& rows) {
  camera::Image image =
      camera::Image::Rgb(static_cast<int>(rows[0].size()), static_cast<int>(rows.size()));
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      uint8_t* p = image.Row(y) + 3 * x;
      const char c = rows[static_cast<size_t>(y)][static_cast<size_t>(x)];
      p[0] = c == 'r' ? 230 : 20;
      p[1] = c == 'g' ? 230 : 20;
      p[2] = 20;
    }
  }
  return image;
}

SegmenterOptions Keep(int min_area_px = 1) {
  SegmenterOptions o;
  o.min_area_px = min_area_px;
  return o;
}

TEST(Segmenter, HandMadeImageRunsAndRegions) {
  Segmenter s(RedGreen(), Keep());
  s.Process(FromText({
      "rr..g",
      "rr.gg",
      "....g",
  }));
  ASSERT_EQ(s.runs().size(), 5u);  // rr g / rr gg / g
  EXPECT_EQ(s.runs()[0].x_begin, 0);
  EXPECT_EQ(s.runs()[0].x_end, 1);
  EXPECT_EQ(s.runs()[3].x_begin, 3);
  EXPECT_EQ(s.runs()[4].y, 2);
  ASSERT_EQ(s.regions().size(), 2u);
  const Region& red = s.regions()[0];
  EXPECT_EQ(red.colour, 0);
  EXPECT_EQ(red.area_px, 4);
  EXPECT_EQ(red.centroid_px, Vec2(0.5, 0.5));
  EXPECT_EQ(red.x_max, 1);
  EXPECT_EQ(red.y_max, 1);
  EXPECT_DOUBLE_EQ(red.Fill(), 1.0);
  const Region& green = s.regions()[1];
  EXPECT_EQ(green.colour, 1);
  EXPECT_EQ(green.area_px, 4);
  // pixels (4,0), (3,1), (4,1), (4,2): mean x = 15/4, mean y = 4/4
  EXPECT_EQ(green.centroid_px, Vec2(3.75, 1.0));
  EXPECT_EQ(green.x_min, 3);
  EXPECT_DOUBLE_EQ(green.Fill(), 4.0 / 6.0);
}

TEST(Segmenter, UnionFindJoinsAUShapeAndAnS) {
  // The two arms of the U meet only on the last row; the S needs joins in both directions.
  Segmenter s(RedGreen(), Keep());
  s.Process(FromText({
      "r.r.ggg",
      "r.r.g..",
      "rrr.ggg",
      "....r.g",
      "r.r.ggg",
  }));
  ASSERT_EQ(s.RegionsOf(0).size(), 4u);  // the U (7 px) and three single pixels
  EXPECT_EQ(s.RegionsOf(0)[0].area_px, 7);
  ASSERT_EQ(s.RegionsOf(1).size(), 1u);
  EXPECT_EQ(s.RegionsOf(1)[0].area_px, 11);
  EXPECT_EQ(s.num_raw_regions(), 5);
}

TEST(Segmenter, DiagonalNeighboursAreSeparateRegions) {
  // 4-connectivity, as CMVision: runs join only when they overlap on adjacent rows.
  Segmenter s(RedGreen(), Keep());
  s.Process(FromText({"r.", ".r"}));
  EXPECT_EQ(s.regions().size(), 2u);
}

TEST(Segmenter, DifferentClassesTouchingStayApart) {
  Segmenter s(RedGreen(), Keep());
  s.Process(FromText({"rrgg", "rrgg"}));
  ASSERT_EQ(s.regions().size(), 2u);
  EXPECT_EQ(s.regions()[0].centroid_px, Vec2(0.5, 0.5));
  EXPECT_EQ(s.regions()[1].centroid_px, Vec2(2.5, 0.5));
}

TEST(Segmenter, FiltersByAreaAndFillAndSortsByArea) {
  const camera::Image image = FromText({
      "r..rr.rrr",
      "...rr.r..",
      "......r..",
  });
  Segmenter all(RedGreen(), Keep());
  all.Process(image);
  ASSERT_EQ(all.regions().size(), 3u);
  EXPECT_EQ(all.regions()[0].area_px, 5);  // the L
  EXPECT_EQ(all.regions()[1].area_px, 4);  // the square
  EXPECT_EQ(all.regions()[2].area_px, 1);
  SegmenterOptions o = Keep(2);
  o.min_fill = 0.6;  // the L fills 5 / 9
  Segmenter filtered(RedGreen(), o);
  filtered.Process(image);
  ASSERT_EQ(filtered.regions().size(), 1u);
  EXPECT_EQ(filtered.regions()[0].area_px, 4);
}

TEST(Segmenter, ClassMinAreaOverridesTheDefault) {
  Thresholds t = RedGreen();
  t.classes[1].min_area_px = 3;
  Segmenter s(t, Keep(1));
  s.Process(FromText({"rg", "r."}));
  ASSERT_EQ(s.regions().size(), 1u);
  EXPECT_EQ(s.regions()[0].colour, 0);
}

TEST(Segmenter, ClassMaxAreaDropsLargerRegions) {
  Thresholds t = RedGreen();
  t.classes[0].max_area_px = 2;  // the 3-pixel red region goes, the 2-pixel green one stays
  Segmenter s(t, Keep(1));
  s.Process(FromText({"rrr.", "...g", "...g"}));
  ASSERT_EQ(s.regions().size(), 1u);
  EXPECT_EQ(s.regions()[0].colour, 1);
  t.classes[0].max_area_px = 3;
  Segmenter kept(t, Keep(1));
  kept.Process(FromText({"rrr.", "...g", "...g"}));
  EXPECT_EQ(kept.regions().size(), 2u);
}

TEST(Segmenter, RunsAcrossWordBoundariesAndRowEnds) {
  // Runs starting and ending at every offset around the 8-byte skipping in EncodeRuns.
  for (int start = 0; start < 19; ++start) {
    for (int length = 1; start + length <= 19; ++length) {
      std::string row(19, '.');
      for (int x = start; x < start + length; ++x) row[static_cast<size_t>(x)] = 'g';
      Segmenter s(RedGreen(), Keep());
      s.Process(FromText({row}));
      ASSERT_EQ(s.regions().size(), 1u) << row;
      EXPECT_EQ(s.regions()[0].x_min, start) << row;
      EXPECT_EQ(s.regions()[0].area_px, length) << row;
    }
  }
}

TEST(Segmenter, YuvThresholdsOnRgbAndUyvyFramesAgree) {
  Thresholds t;
  t.space = ColorSpace::kYuv;
  ColorClass blue;
  blue.name = "blue";
  blue.range = {ChannelRange{0, 255}, ChannelRange{160, 255}, ChannelRange{0, 120}};
  t.classes = {blue};
  std::vector<render::Disc> discs = {{Vec2(20.3, 15.7), 6.2, {30, 40, 220}}};
  const camera::Image rgb = render::RenderDiscs(40, 30, {90, 90, 90}, discs);
  Segmenter a(t, Keep()), b(t, Keep());
  a.Process(rgb);
  b.Process(camera::ToUyvy(rgb));
  ASSERT_EQ(a.regions().size(), 1u);
  ASSERT_EQ(b.regions().size(), 1u);
  // Digitisation error < 0.15 px at this radius (see the test below); UYVY's shared chroma
  // moves boundary pixels by up to one more column, hence 0.25 px.
  EXPECT_NEAR(a.regions()[0].centroid_px.x(), 20.3, 0.15);
  EXPECT_NEAR(a.regions()[0].centroid_px.y(), 15.7, 0.15);
  EXPECT_NEAR(b.regions()[0].centroid_px.x(), 20.3, 0.25);
  EXPECT_NEAR(b.regions()[0].centroid_px.y(), 15.7, 0.25);
  // Chroma subsampling moves boundary pixels only: areas within one boundary's worth.
  EXPECT_NEAR(a.regions()[0].area_px, b.regions()[0].area_px, 2 * M_PI * 6.2 * 0.5);
}

// Rendered anti-aliased discs at random sub-pixel positions: the centroid of the thresholded
// disc is the disc centre up to digitisation, which shrinks with the radius (measured over 400
// discs: max per axis 0.22 px at r = 4, 0.15 at r = 6..8, 0.16 for r in 12..20; rms 0.075 at
// r = 4 falling to 0.03 at r = 20). The mean error
// over many discs must vanish within 4 standard errors (no bias: the pixel-centre convention and
// the run sums are right; a half-pixel slip would fail by 25 standard errors).
void CheckDiscCentroids(double min_radius, double max_radius, double max_error_px) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Segmenter s(RedGreen(), Keep());
  const int n = 200;
  double sum[2] = {0, 0}, sum_sq[2] = {0, 0}, max_error = 0.0;
  for (int trial = 0; trial < n; ++trial) {
    const double radius = min_radius + (max_radius - min_radius) * unit(rng);
    const Vec2 centre(30 + unit(rng), 30 + unit(rng));
    const std::vector<render::Disc> discs = {{centre, radius, {240, 10, 10}}};
    s.Process(render::RenderDiscs(61, 61, {10, 10, 10}, discs, 16));
    ASSERT_EQ(s.regions().size(), 1u);
    const Vec2 error = s.regions()[0].centroid_px - centre;
    for (int k = 0; k < 2; ++k) {
      sum[k] += error[k];
      sum_sq[k] += error[k] * error[k];
      max_error = std::max(max_error, std::abs(error[k]));
    }
    // Area within half a pixel ring of pi r^2.
    EXPECT_NEAR(s.regions()[0].area_px, M_PI * radius * radius, 2 * M_PI * radius * 0.5);
  }
  EXPECT_LT(max_error, max_error_px);
  for (int k = 0; k < 2; ++k) {
    const double mean = sum[k] / n;
    const double standard_error = std::sqrt((sum_sq[k] / n - mean * mean) / (n - 1));
    EXPECT_LT(std::abs(mean), 4 * standard_error) << "axis " << k;
  }
}

TEST(Segmenter, CentroidsOfRenderedDiscsAreSubPixelAccurate) {
  CheckDiscCentroids(4, 8, 0.3);
  CheckDiscCentroids(12, 20, 0.2);
}

TEST(Segmenter, ManyDiscsAllFoundInAreaOrder) {
  std::vector<render::Disc> discs;
  for (int i = 0; i < 12; ++i) {
    discs.push_back({Vec2(20 + 40 * (i % 4) + 0.25 * i, 20 + 40 * (i / 4) + 0.1 * i), 5.0 + i,
                     i % 2 ? render::Rgb{10, 240, 10} : render::Rgb{240, 10, 10}});
  }
  Segmenter s(RedGreen(), Keep(10));
  s.Process(render::RenderDiscs(170, 130, {0, 0, 0}, discs));
  ASSERT_EQ(s.RegionsOf(0).size(), 6u);
  ASSERT_EQ(s.RegionsOf(1).size(), 6u);
  for (int c = 0; c < 2; ++c) {
    const auto regions = s.RegionsOf(c);
    for (size_t k = 0; k < regions.size(); ++k) {
      const render::Disc& d =
          discs[static_cast<size_t>(10 + c - 2 * static_cast<int>(k))];  // largest first
      EXPECT_NEAR(regions[k].centroid_px.x(), d.centre.x(), 0.1);
      EXPECT_NEAR(regions[k].centroid_px.y(), d.centre.y(), 0.1);
    }
  }
}

TEST(Segmenter, OptionsAreValidated) {
  SegmenterOptions o;
  o.min_area_px = 0;
  EXPECT_INPUT_ERROR(Validate(o), "min_area_px is 0; expected an integer >= 1");
  o.min_area_px = 1;
  o.min_fill = 1.5;
  EXPECT_INPUT_ERROR(Validate(o), "min_fill is 1.5; expected a number in [0, 1]");
  o.min_area_px = -3;  // Check reports every broken constraint
  const std::vector<OptionsProblem> problems = Check(o);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].field, "min_area_px");
  EXPECT_EQ(problems[1].field, "min_fill");
}

}  // namespace
}  // namespace patlab::vision

namespace patlab::vision {
namespace {

// RGB frames with YUV thresholds are classified a row at a time (the row converted to Y/U/V planes
// in 16-bit lanes, then a byte range test per class, the first-listed class winning): every pixel
// must get the class ColorLut gives its exact BT.601 YUV value.
TEST(Segmenter, RgbRowClassificationIsExactForYuvThresholds) {
  const Thresholds t = formats::ParseCmvisionColors(
      "[Colors]\n(1,1,1) 0.5 1 a\n(1,1,1) 0.5 1 b\n(1,1,1) 0.5 1 c\n[Thresholds]\n"
      "(60:160, 60:115, 160:200)\n(100:255, 0:95, 135:175)\n(30:160, 150:255, 60:125)\n",
      "t.txt");
  camera::Image image = camera::Image::Rgb(256, 256);
  std::mt19937 rng(3);
  for (uint8_t& v : image.data) v = static_cast<uint8_t>(rng());
  SegmenterOptions o;
  o.min_area_px = 1;
  Segmenter s(t, o);
  s.Classify(image);
  int mismatches = 0;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const uint8_t* p = image.Row(y) + 3 * x;
      int yy, uu, vv;
      camera::RgbToYuv(p[0], p[1], p[2], &yy, &uu, &vv);
      mismatches +=
          s.class_image()[static_cast<size_t>(y * 256 + x)] != s.lut().Classify(yy, uu, vv) + 1;
    }
  }
  EXPECT_EQ(mismatches, 0);
}

// Every one of the 2^24 RGB colours, with the thresholds of the real frames (7 and 8 classes,
// overlapping boxes, a black class whose U/V bounds cut through the carpet's cells). The width,
// 4099, is not a multiple of any vector width, so row tails are covered too.
TEST(Segmenter, RgbRowClassificationIsExactForEveryColour) {
  constexpr int kWidth = 4099, kHeight = ((1 << 24) + kWidth - 1) / kWidth;
  for (const char* file : {"ssl-2008.thresholds.toml", "vss.colors.txt"}) {
    const Thresholds t =
        formats::LoadThresholds(std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/" + file);
    camera::Image image = camera::Image::Rgb(kWidth, kHeight);
    const int n = kWidth * kHeight;
    for (int i = 0; i < n; ++i) {
      const int c = i & 0xffffff;
      uint8_t* p = image.data.data() + 3 * static_cast<size_t>(i);
      p[0] = static_cast<uint8_t>(c >> 16);
      p[1] = static_cast<uint8_t>(c >> 8);
      p[2] = static_cast<uint8_t>(c);
    }
    SegmenterOptions o;
    o.min_area_px = 1;
    Segmenter s(t, o);
    s.Classify(image);
    long mismatches = 0;
    for (int i = 0; i < n; ++i) {
      const int c = i & 0xffffff;
      int yy, uu, vv;
      camera::RgbToYuv(c >> 16, (c >> 8) & 255, c & 255, &yy, &uu, &vv);
      mismatches += s.class_image()[static_cast<size_t>(i)] != s.lut().Classify(yy, uu, vv) + 1;
    }
    EXPECT_EQ(mismatches, 0) << file;
  }
}

}  // namespace
}  // namespace patlab::vision

namespace patlab::vision {
namespace {

// Stage 3's runs against the plain definition (a run ends where the class changes), on rows of
// random runs from 1 to 100 pixels of no class, red and green, 1 to 200 pixels wide: runs start
// and end at every offset around EncodeRuns' 32- and 8-pixel strides and at the row ends.
TEST(Segmenter, RunsAreThoseOfThePlainDefinition) {
  std::mt19937 rng(11);
  for (int width = 1; width <= 200; ++width) {
    std::vector<std::string> rows(6, std::string(static_cast<size_t>(width), '.'));
    for (std::string& row : rows) {
      for (int x = 0; x < width;) {
        const int length = 1 + static_cast<int>(rng() % (rng() % 2 == 0 ? 8 : 100));
        const char c = ".rg"[rng() % 3];
        for (int k = x; k < std::min(width, x + length); ++k) row[static_cast<size_t>(k)] = c;
        x += length;
      }
    }
    Segmenter s(RedGreen(), Keep());
    s.Process(FromText(rows));
    std::vector<std::array<int, 4>> want, got;  // x_begin, x_end, y, colour
    for (int y = 0; y < static_cast<int>(rows.size()); ++y) {
      const std::string& row = rows[static_cast<size_t>(y)];
      for (int x = 0; x < width;) {
        int end = x;
        while (end + 1 < width &&
               row[static_cast<size_t>(end + 1)] == row[static_cast<size_t>(x)]) {
          ++end;
        }
        if (row[static_cast<size_t>(x)] != '.') {
          want.push_back({x, end, y, row[static_cast<size_t>(x)] == 'r' ? 0 : 1});
        }
        x = end + 1;
      }
    }
    for (const vision::Run& r : s.runs()) got.push_back({r.x_begin, r.x_end, r.y, r.colour});
    ASSERT_EQ(got, want) << "width " << width;
  }
}

// Random boxes, one per class.
Thresholds RandomBoxes(ColorSpace space, int classes, std::mt19937& rng) {
  Thresholds t;
  t.space = space;
  for (int k = 0; k < classes; ++k) {
    ColorClass c;
    c.name = "c";
    c.name += std::to_string(k);
    for (ChannelRange& r : c.range) {
      const int a = static_cast<int>(rng() % 256), b = static_cast<int>(rng() % 256);
      r = {std::min(a, b), std::max(a, b)};
    }
    t.classes.push_back(c);
  }
  return t;
}

// Pixel (x, y) of an RGB or UYVY frame in the colour space `space` (image.h's conversions).
std::array<int, 3> PixelIn(const camera::Image& image, int x, int y, ColorSpace space) {
  int a, b, c;
  if (image.format == camera::PixelFormat::kUyvy) {
    const uint8_t* pair = image.Row(y) + 4 * (x / 2);
    a = pair[1 + 2 * (x % 2)], b = pair[0], c = pair[2];
    if (space == ColorSpace::kRgb) camera::YuvToRgb(a, b, c, &a, &b, &c);
  } else {
    const uint8_t* p = image.Row(y) + 3 * x;
    a = p[0], b = p[1], c = p[2];
    if (space == ColorSpace::kYuv) camera::RgbToYuv(a, b, c, &a, &b, &c);
  }
  return {a, b, c};
}

// Stage 2 against ColorLut on every pixel, for each frame format and thresholds space, with
// 1, 3, 8 (byte tables, where the build has them) and 9, 12 classes (box tests): random boxes,
// random pixels, rows whose width is no multiple of a vector's.
TEST(Segmenter, ClassesAreColorLutsForEveryFormatSpaceAndClassCount) {
  std::mt19937 rng(5);
  for (const ColorSpace space : {ColorSpace::kYuv, ColorSpace::kRgb}) {
    for (const int classes : {1, 3, 8, 9, 12}) {
      const Thresholds t = RandomBoxes(space, classes, rng);
      for (const bool uyvy : {false, true}) {
        camera::Image image =
            uyvy ? camera::ToUyvy(camera::Image::Rgb(98, 37)) : camera::Image::Rgb(98, 37);
        for (uint8_t& v : image.data) v = static_cast<uint8_t>(rng());  // any U, Y, V too
        Segmenter s(t, Keep());
        s.Classify(image);
        long mismatches = 0;
        for (int y = 0; y < image.height_px; ++y) {
          for (int x = 0; x < image.width_px; ++x) {
            const auto [a, b, c] = PixelIn(image, x, y, space);
            mismatches += s.class_image()[static_cast<size_t>(y * image.width_px + x)] !=
                          s.lut().Classify(a, b, c) + 1;
          }
        }
        EXPECT_EQ(mismatches, 0) << classes << " classes, uyvy " << uyvy << ", space "
                                 << static_cast<int>(space);
      }
    }
  }
}

// The portable row conversion (two passes: planes, then arithmetic) is image.h's RgbToYuv for
// every RGB colour, in rows of 4099 pixels and of every length from 1 to 100.
TEST(Segmenter, PortableRowConversionIsRgbToYuv) {
  constexpr int kLong = 4099;
  std::vector<uint8_t> in(3 * static_cast<size_t>(kLong)), out(in.size());
  long mismatches = 0;
  const auto compare = [&](int n) {
    uint8_t* o = out.data();
    internal::RgbRowToYuv(in.data(), n, o, o + n, o + 2 * n);
    for (int i = 0; i < n; ++i) {
      int y, u, v;
      camera::RgbToYuv(in[3 * i], in[3 * i + 1], in[3 * i + 2], &y, &u, &v);
      mismatches += (o[i] != y) + (o[n + i] != u) + (o[2 * n + i] != v);
    }
  };
  for (int first = 0; first < (1 << 24); first += kLong) {
    for (int i = 0; i < kLong; ++i) {
      const int c = (first + i) & 0xffffff;
      in[3 * static_cast<size_t>(i)] = static_cast<uint8_t>(c >> 16);
      in[3 * static_cast<size_t>(i) + 1] = static_cast<uint8_t>(c >> 8);
      in[3 * static_cast<size_t>(i) + 2] = static_cast<uint8_t>(c);
    }
    compare(kLong);
  }
  for (int n = 1; n <= 100; ++n) compare(n);
  EXPECT_EQ(mismatches, 0);
}

// The AVX-512 row conversion gives the portable loop's bytes for every RGB colour, in rows of
// every length from 1 to 100 (the masked last block) and a long one.
TEST(Segmenter, Avx512RowConversionIsThePortableOnes) {
  if (!internal::HaveAvx512Rows()) GTEST_SKIP() << "this build has no AVX-512 row conversion";
  constexpr int kLong = 4099;
  std::vector<uint8_t> in(3 * static_cast<size_t>(kLong));
  std::vector<uint8_t> want(3 * static_cast<size_t>(kLong)), got(want.size());
  long mismatches = 0;
  const auto compare = [&](int n) {
    uint8_t* w = want.data();
    uint8_t* g = got.data();
    std::fill(got.begin(), got.end(), 0xA5);
    internal::RgbRowToYuv(in.data(), n, w, w + n, w + 2 * n);
    internal::RgbRowToYuvAvx512(in.data(), n, g, g + n, g + 2 * n);
    for (int i = 0; i < 3 * n; ++i) mismatches += w[i] != g[i];
    for (size_t i = 3 * static_cast<size_t>(n); i < got.size(); ++i) mismatches += g[i] != 0xA5;
  };
  for (int first = 0; first < (1 << 24); first += kLong) {
    for (int i = 0; i < kLong; ++i) {
      const int c = (first + i) & 0xffffff;
      in[3 * static_cast<size_t>(i)] = static_cast<uint8_t>(c >> 16);
      in[3 * static_cast<size_t>(i) + 1] = static_cast<uint8_t>(c >> 8);
      in[3 * static_cast<size_t>(i) + 2] = static_cast<uint8_t>(c);
    }
    compare(kLong);
  }
  for (int n = 1; n <= 100; ++n) compare(n);
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace patlab::vision

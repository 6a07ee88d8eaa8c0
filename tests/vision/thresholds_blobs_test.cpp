// The colour fit from patch blobs (vision/thresholds_blobs.h) on synthetic frames with known
// answers: patches stand out from the carpet around them under a light that falls fourfold, the
// blobs are the discs drawn and lines are none, two clusters competing for a name get the names
// that fit them best together, clutter gets none, the boxes classify every disc and no carpet, and
// a class fitted from one blob holds its colour's other patches under the camera's noise.
#include "patlab/vision/thresholds_blobs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "patlab/io/colour_vocabulary.h"
#include "patlab/vision/color_lut.h"

namespace patlab::vision {
namespace {

struct Disc {
  double x, y, r;
  std::array<uint8_t, 3> rgb;
};

// A carpet (40, 100, 50) whose light falls from 1.0 at the left edge to `right_gain` at the right
// (on linear intensities, approximated on levels by a gamma of 2.2), with discs under the same
// light.
camera::Image Frame(int w, int h, const std::vector<Disc>& discs, double right_gain) {
  camera::Image image = camera::Image::Rgb(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::array<uint8_t, 3> c = {40, 100, 50};
      for (const Disc& d : discs) {
        if (std::hypot(x - d.x, y - d.y) <= d.r) c = d.rgb;
      }
      const double gain = 1.0 + (right_gain - 1.0) * x / (w - 1.0);
      const double level_gain = std::pow(gain, 1.0 / 2.2);
      uint8_t* p = image.Row(y) + 3 * x;
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<uint8_t>(std::clamp(std::lround(c[k] * level_gain), 0L, 255L));
    }
  }
  return image;
}

double DeltaE(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(ThresholdsBlobs, PatchesStandOutFromTheCarpetAroundThemWhereverTheLightIs) {
  // The light falls fourfold from left to right: the carpet's right end lies farther from its
  // mean colour than the stand-out distance, yet no carpet pixel is a candidate, and the three
  // discs are the three blobs.
  const std::array<uint8_t, 3> yellow = {200, 180, 40};
  const std::vector<Disc> discs = {
      {30, 60, 7, yellow}, {210, 60, 7, yellow}, {120, 30, 5, {40, 70, 200}}};
  const camera::Image image = Frame(240, 120, discs, 0.25);
  BlobThresholdsOptions o;
  o.max_light_gain = 4.0;
  o.standout_delta_e = 10.0;
  const NormalisedFrame f = NormaliseFrame(image, o);
  EXPECT_GT(f.carpet_pixels, 240 * 120 * 8 / 10);
  const uint8_t* dark = image.Row(110) + 3 * 239;
  std::array<double, 3> mean_raw{};
  long n = 0;
  for (size_t i = 0; i < f.lab.size(); ++i) {
    if (f.carpet[i] == 0) continue;
    for (int k = 0; k < 3; ++k) mean_raw[k] += f.lab[i][k];
    ++n;
  }
  for (double& v : mean_raw) v /= static_cast<double>(n);
  ASSERT_GT(DeltaE(SrgbToLab({dark[0], dark[1], dark[2]}), mean_raw), o.standout_delta_e);
  long carpet_candidates = 0, disc_candidates = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 240; ++x) {
      bool on_disc = false;
      for (const Disc& d : discs) on_disc = on_disc || std::hypot(x - d.x, y - d.y) <= d.r;
      const bool candidate = f.standout_delta_e2[static_cast<size_t>(y) * 240 + x] >
                             o.standout_delta_e * o.standout_delta_e;
      (on_disc ? disc_candidates : carpet_candidates) += candidate ? 1 : 0;
    }
  EXPECT_EQ(carpet_candidates, 0);
  EXPECT_GT(disc_candidates, static_cast<long>(0.9 * M_PI * (49 + 49 + 25)));
  const std::vector<ColourBlob> blobs = FindColourBlobs(f, 0, o);
  ASSERT_EQ(blobs.size(), 3u);
  // In the order of their first pixel: the blue disc (row 25), then the two yellow ones.
  EXPECT_NEAR(blobs[0].x_px, 120.0, 0.3);
  EXPECT_NEAR(blobs[0].y_px, 30.0, 0.3);
  EXPECT_NEAR(static_cast<double>(blobs[0].pixels.size()), M_PI * 25, 12.0);
  EXPECT_NEAR(blobs[0].sigma_minor_px, 2.5, 0.3);
  EXPECT_NEAR(blobs[1].x_px, 30.0, 0.3);
  EXPECT_NEAR(blobs[2].x_px, 210.0, 0.3);
}

TEST(ThresholdsBlobs, LinesAreNoBlobs) {
  // A white line 3 px wide and 40 px long is of a patch's area but not its width.
  camera::Image image = Frame(120, 80, {{90, 40, 6, {235, 215, 45}}}, 1.0);
  for (int y = 20; y < 60; ++y)
    for (int x = 20; x < 23; ++x)
      for (int k = 0; k < 3; ++k) image.Row(y)[3 * x + k] = 240;
  BlobThresholdsOptions o;
  o.min_blob_sigma_px = 1.5;
  const std::vector<ColourBlob> blobs = FindColourBlobs(NormaliseFrame(image, o), 0, o);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].x_px, 90.0, 0.3);
  o.min_blob_sigma_px = 0.5;
  EXPECT_EQ(FindColourBlobs(NormaliseFrame(image, o), 0, o).size(), 2u);
}

TEST(ThresholdsBlobs, CompetingClustersTakeTheNamesThatFitThemTogether) {
  // A salmon pink (the SSL frame's "pink" dots, hue near red) is nearer the vocabulary's orange
  // than its pink by hue alone; with a real orange ball in the frame the pair is named pink and
  // orange.
  const ColourVocabulary& vocabulary = io::DefaultColourVocabulary();
  const BlobThresholdsOptions o;
  const std::array<double, 3> salmon = SrgbToLab({236, 137, 136});
  const std::array<double, 3> ball = SrgbToLab({200, 90, 30});
  const ColourEntry& pink = *vocabulary.Find("pink");
  const ColourEntry& orange = *vocabulary.Find("orange");
  ASSERT_LT(NameCost(salmon, orange, o), NameCost(salmon, pink, o));  // the trap
  std::vector<ColourBlob> blobs;
  const auto blob = [](const std::array<double, 3>& lab) {
    ColourBlob b;
    b.lab = lab;
    return b;
  };
  for (int i = 0; i < 5; ++i) blobs.push_back(blob(salmon));
  blobs.push_back(blob(ball));
  blobs.push_back(blob(SrgbToLab({0, 200, 220})));  // cyan: neither pink nor orange
  const std::vector<BlobCluster> clusters = NameBlobClusters({&pink, &orange}, o, &blobs);
  ASSERT_EQ(clusters.size(), 3u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(blobs[static_cast<size_t>(i)].name, 0) << i;
  EXPECT_EQ(blobs[5].name, 1);
  EXPECT_EQ(blobs[6].name, -1);
  EXPECT_EQ(clusters[static_cast<size_t>(blobs[0].cluster)].blobs, 5);
}

TEST(ThresholdsBlobs, DarkBlobsDoNotChainIntoOneBlackCluster) {
  // The dark blobs of the real SSL frame, rounded: black sectors and shadows (L* 6-23, almost no
  // chroma), beige walls and dark rims (L* 34-46), a dull orange ball between them, white
  // sectors. Each blob lies within the cluster distance of the next darker one, so clusters whose
  // centre follows what they take in chained them into one cluster spanning 40 L*, named black:
  // the ball was black and orange named nothing. Now black is the dark blobs, the ball orange
  // and the walls, a grey 20 L* above black's, nothing.
  const ColourVocabulary& vocabulary = io::DefaultColourVocabulary();
  const BlobThresholdsOptions o;
  const std::vector<std::array<double, 3>> dark = {{6, 0, 2},   {8, 1, 3},  {10, -1, 1},
                                                   {11, -7, 1}, {21, 3, 6}, {23, -2, 5}};
  const std::vector<std::array<double, 3>> walls = {{34, -2, 10}, {37, -2, 12}, {39, -1, 12},
                                                    {42, 0, 19},  {44, -6, 16}, {46, 7, 16}};
  std::vector<ColourBlob> blobs;
  const auto add = [&](const std::array<double, 3>& lab) {
    ColourBlob b;
    b.lab = lab;
    blobs.push_back(b);
  };
  for (const auto& lab : dark) add(lab);
  for (const auto& lab : walls) add(lab);
  add({37, 18, 29});  // the ball
  for (int i = 0; i < 3; ++i) add({96, -2, 9});
  NameBlobClusters({vocabulary.Find("black"), vocabulary.Find("white"), vocabulary.Find("orange")},
                   o, &blobs);
  for (size_t i = 0; i < dark.size(); ++i) EXPECT_EQ(blobs[i].name, 0) << i;
  for (size_t i = dark.size(); i < dark.size() + walls.size(); ++i)
    EXPECT_EQ(blobs[i].name, -1) << i;
  EXPECT_EQ(blobs[12].name, 2);
  for (size_t i = 13; i < 16; ++i) EXPECT_EQ(blobs[i].name, 1) << i;
}

TEST(ThresholdsBlobs, AchromaticEntriesTakeLightnessNotHue) {
  const ColourVocabulary& vocabulary = io::DefaultColourVocabulary();
  const BlobThresholdsOptions o;
  const std::array<double, 3> grey_white = SrgbToLab({235, 238, 225});
  EXPECT_LT(NameCost(grey_white, *vocabulary.Find("white"), o), 1.0);
  // Only the lightness (85 L* apart) tells white from black: over the 40 L* spread, 4.5.
  EXPECT_GT(NameCost(grey_white, *vocabulary.Find("black"), o), 4.0);
  EXPECT_GT(NameCost(SrgbToLab({220, 200, 40}), *vocabulary.Find("white"), o), 9.0);
}

TEST(ThresholdsBlobs, BoxesClassifyEveryDiscAndNoCarpet) {
  const std::vector<Disc> discs = {{30, 30, 6, {235, 215, 45}},  {90, 30, 6, {35, 75, 210}},
                                   {150, 30, 6, {240, 95, 185}}, {30, 90, 6, {235, 215, 45}},
                                   {90, 90, 6, {35, 75, 210}},   {150, 90, 6, {240, 95, 185}},
                                   {210, 60, 4, {250, 125, 25}}, {210, 100, 6, {140, 50, 200}}};
  const camera::Image image = Frame(240, 120, discs, 0.5);
  std::vector<BlobCluster> clusters;
  const AutoThresholdsFit fit = FitThresholdsFromBlobs(
      {&image}, {"yellow", "blue", "pink", "orange"}, io::DefaultColourVocabulary(), {}, &clusters);
  ASSERT_EQ(fit.classes.size(), 4u);
  EXPECT_EQ(fit.classes[0].blobs, 2);
  EXPECT_EQ(fit.classes[1].blobs, 2);
  EXPECT_EQ(fit.classes[2].blobs, 2);
  EXPECT_EQ(fit.classes[3].blobs, 1);
  const ColorLut lut(fit.thresholds);
  const auto classify = [&](int x, int y) {
    const uint8_t* p = image.Row(y) + 3 * x;
    int a, b, c;
    camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
    return lut.Classify(a, b, c);
  };
  const int expected[] = {0, 1, 2, 0, 1, 2, 3, -1};
  for (size_t i = 0; i < discs.size(); ++i) {
    EXPECT_EQ(classify(static_cast<int>(discs[i].x), static_cast<int>(discs[i].y)), expected[i])
        << i;
  }
  long carpet_caught = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 240; ++x) {
      bool on_disc = false;
      for (const Disc& d : discs) on_disc = on_disc || std::hypot(x - d.x, y - d.y) <= d.r + 1.5;
      if (!on_disc && classify(x, y) >= 0) ++carpet_caught;
    }
  EXPECT_EQ(carpet_caught, 0);
}

// Adds Gaussian noise of `sigma` levels to every channel of every pixel (Box-Muller on a fixed
// seed, the same on every platform).
void AddNoise(double sigma, camera::Image* image) {
  std::mt19937 rng(7);
  const auto uniform = [&] { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; };
  for (int y = 0; y < image->height_px; ++y) {
    for (int x = 0; x < 3 * image->width_px; ++x) {
      const double g = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
      uint8_t& p = image->Row(y)[x];
      p = static_cast<uint8_t>(std::clamp(std::lround(p + sigma * g), 0L, 255L));
    }
  }
}

TEST(ThresholdsBlobs, AClassFittedFromOneBlobHoldsItsColoursOtherPatchesUnderTheNoise) {
  // One blue disc large enough to be a blob (95 px) and eight smaller ones that are not (50 px
  // each, under the blob area; as keys that made no blob in a frame), all of one colour under
  // noise of 3 levels. The class is fitted from the one blob's pixels; the other discs' pixels,
  // four times as many, are among the frame's "other" pixels its box is tightened against, so the
  // box used to be pulled in to a sliver of the noise and caught 0-6 of each disc's 30-37 inner
  // pixels. Widened towards the noise measured on the carpet, it holds at least 4 in 5.
  const std::array<uint8_t, 3> blue = {35, 75, 210};
  std::vector<Disc> discs = {{40, 60, 5.5, blue}};
  for (int i = 0; i < 8; ++i)
    discs.push_back({100.0 + 40.0 * (i % 4), 35.0 + 50.0 * (i / 4), 4.0, blue});
  camera::Image image = Frame(280, 120, discs, 1.0);
  AddNoise(3.0, &image);
  BlobThresholdsOptions o;
  o.min_blob_area_px = 60.0;
  const AutoThresholdsFit fit =
      FitThresholdsFromBlobs({&image}, {"blue"}, io::DefaultColourVocabulary(), o);
  ASSERT_EQ(fit.classes.size(), 1u);
  ASSERT_EQ(fit.classes[0].blobs, 1);
  // The noise measured: 3 levels on R, G and B are about 2 on Y, U and V, whose 2nd to 98th
  // percentiles span about 8 levels.
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_GE(fit.noise_levels[ch], 6) << ch;
    EXPECT_LE(fit.noise_levels[ch], 11) << ch;
  }
  const ColorLut lut(fit.thresholds);
  for (size_t d = 1; d < discs.size(); ++d) {
    long inside = 0, caught = 0;
    for (int y = 0; y < image.height_px; ++y) {
      for (int x = 0; x < image.width_px; ++x) {
        if (std::hypot(x - discs[d].x, y - discs[d].y) > discs[d].r - 0.5) continue;
        const uint8_t* p = image.Row(y) + 3 * x;
        int a, b, c;
        camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
        ++inside;
        caught += lut.Classify(a, b, c) == 0 ? 1 : 0;
      }
    }
    EXPECT_GE(caught, 0.8 * inside) << "disc " << d;
  }
  EXPECT_GT(fit.classes[0].widened_levels[0] + fit.classes[0].widened_levels[1] +
                fit.classes[0].widened_levels[2],
            0);
  // The carpet, under the same noise, stays out.
  long carpet_caught = 0;
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      bool on_disc = false;
      for (const Disc& d : discs) on_disc = on_disc || std::hypot(x - d.x, y - d.y) <= d.r + 1.5;
      const uint8_t* p = image.Row(y) + 3 * x;
      int a, b, c;
      camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
      if (!on_disc && lut.Classify(a, b, c) >= 0) ++carpet_caught;
    }
  }
  EXPECT_EQ(carpet_caught, 0);
}

TEST(ThresholdsBlobs, AClassKeepsItsPatchesWhoseCoresAreTooNarrowForABlob) {
  // Four blue discs that are blobs (50 px each) and forty blue bars of a patch's area but 2 px
  // wide (spread 0.58 px, under min_blob_sigma_px: as a small patch's bright core that the
  // segmentation cut to a sliver), all of one colour under noise of 3 levels. The bars' pixels,
  // five times the blobs', used to count among the frame's "other" pixels against the class's
  // box, which was pulled in until it caught 973 of their 1120 pixels (87 %). Regions too narrow
  // for a blob that hold the class's median colour spread by the camera's noise no longer count
  // against it: 1117.
  const std::array<uint8_t, 3> blue = {35, 75, 210};
  const std::vector<Disc> discs = {
      {30, 25, 4.0, blue}, {30, 65, 4.0, blue}, {30, 105, 4.0, blue}, {30, 145, 4.0, blue}};
  camera::Image image = Frame(320, 170, discs, 1.0);
  struct Bar {
    int x, y;  // top left; 2 px wide, 14 px tall
  };
  std::vector<Bar> bars;
  for (int i = 0; i < 40; ++i) bars.push_back({70 + 24 * (i % 10), 10 + 40 * (i / 10)});
  for (const Bar& b : bars)
    for (int y = b.y; y < b.y + 14; ++y)
      for (int x = b.x; x < b.x + 2; ++x)
        for (int k = 0; k < 3; ++k) image.Row(y)[3 * x + k] = blue[static_cast<size_t>(k)];
  AddNoise(3.0, &image);
  BlobThresholdsOptions o;
  const AutoThresholdsFit fit =
      FitThresholdsFromBlobs({&image}, {"blue"}, io::DefaultColourVocabulary(), o);
  ASSERT_EQ(fit.classes.size(), 1u);
  ASSERT_EQ(fit.classes[0].blobs, 4);
  // The bars' pixels, spared (a bar the noise cut leaves a piece under the blob area out).
  EXPECT_GE(fit.classes[0].thin_alike, 40 * 2 * 14 * 9 / 10);
  EXPECT_LE(fit.classes[0].thin_alike, 40 * 2 * 14);
  const ColorLut lut(fit.thresholds);
  const auto caught = [&](int x, int y) {
    const uint8_t* p = image.Row(y) + 3 * x;
    int a, b, c;
    camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
    return lut.Classify(a, b, c) == 0;
  };
  long in_box = 0;
  for (const Bar& b : bars)
    for (int y = b.y; y < b.y + 14; ++y)
      for (int x = b.x; x < b.x + 2; ++x) in_box += caught(x, y) ? 1 : 0;
  EXPECT_GE(in_box, 0.97 * 40 * 2 * 14) << in_box;
  long carpet_caught = 0;
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      bool near = false;
      for (const Disc& d : discs) near = near || std::hypot(x - d.x, y - d.y) <= d.r + 1.5;
      for (const Bar& b : bars)
        near = near || (x >= b.x - 1 && x <= b.x + 2 && y >= b.y - 1 && y <= b.y + 14);
      if (!near && caught(x, y)) ++carpet_caught;
    }
  }
  EXPECT_EQ(carpet_caught, 0);
}

TEST(ThresholdsBlobs, ABlackBoxKeepsItsPatchesBesideADarkMargin) {
  // Black discs on the carpet beside a dark margin (a wall in shadow, levels 5-70 down the frame)
  // of twenty times their pixels: every box that holds the discs holds more of the margin, and the
  // box, pulled in by its best single move, used to shut on a bin that holds neither (the black
  // class caught nothing). A tightened box keeps the class's median colour.
  const std::vector<Disc> discs = {{120, 30, 6, {18, 18, 20}},
                                   {180, 30, 6, {18, 18, 20}},
                                   {120, 90, 6, {18, 18, 20}},
                                   {180, 90, 6, {18, 18, 20}},
                                   {150, 60, 6, {235, 215, 45}}};
  camera::Image image = Frame(240, 120, discs, 1.0);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 60; ++x)
      for (int k = 0; k < 3; ++k)
        image.Row(y)[3 * x + k] = static_cast<uint8_t>(5 + (65 * y) / 119 + (x + k) % 3);
  const AutoThresholdsFit fit =
      FitThresholdsFromBlobs({&image}, {"black", "yellow"}, io::DefaultColourVocabulary(), {});
  ASSERT_EQ(fit.classes.size(), 2u);
  EXPECT_EQ(fit.classes[0].blobs, 4);
  const ColorLut lut(fit.thresholds);
  for (const Disc& d : discs) {
    const uint8_t* p = image.Row(static_cast<int>(d.y)) + 3 * static_cast<int>(d.x);
    int a, b, c;
    camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
    EXPECT_EQ(lut.Classify(a, b, c), d.rgb[0] == 18 ? 0 : 1) << d.x << ", " << d.y;
  }
}

TEST(ThresholdsBlobs, AWhiteBoxKeepsThePatchesOfALinesTint) {
  // Four white discs and one of the field line's yellowish white: the line holds far more pixels
  // of that tint than the disc, and the box, pulled in against them, used to lose the disc. The
  // line is one region larger than a patch, which the detector's area test rejects whatever its
  // class: it no longer counts against a box.
  const std::array<uint8_t, 3> white = {245, 245, 245}, tint = {235, 228, 190};
  const std::vector<Disc> discs = {{30, 25, 6, white},
                                   {90, 25, 6, white},
                                   {150, 25, 6, white},
                                   {210, 25, 6, white},
                                   {120, 95, 6, tint}};
  camera::Image image = Frame(240, 120, discs, 1.0);
  for (int y = 58; y < 62; ++y)
    for (int x = 0; x < 240; ++x)
      for (int k = 0; k < 3; ++k) image.Row(y)[3 * x + k] = tint[static_cast<size_t>(k)];
  BlobThresholdsOptions o;
  o.max_blob_area_px = 300.0;
  o.min_blob_sigma_px = 1.5;
  const AutoThresholdsFit fit =
      FitThresholdsFromBlobs({&image}, {"white"}, io::DefaultColourVocabulary(), o);
  ASSERT_EQ(fit.classes.size(), 1u);
  EXPECT_EQ(fit.classes[0].blobs, 5);
  const ColorLut lut(fit.thresholds);
  for (const Disc& d : discs) {
    const uint8_t* p = image.Row(static_cast<int>(d.y)) + 3 * static_cast<int>(d.x);
    int a, b, c;
    camera::RgbToYuv(p[0], p[1], p[2], &a, &b, &c);
    EXPECT_EQ(lut.Classify(a, b, c), 0) << d.x << ", " << d.y;
  }
}

TEST(ThresholdsBlobs, BadOptionsNameTheField) {
  BlobThresholdsOptions o;
  o.max_blob_area_px = 2.0;
  o.min_blob_area_px = 5.0;
  const auto problems = Check(o);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].field, "max_blob_area_px");
}

}  // namespace
}  // namespace patlab::vision

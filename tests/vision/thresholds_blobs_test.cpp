// The colour fit from patch blobs (vision/thresholds_blobs.h) on synthetic frames with known
// answers: the light normalisation gives one colour to one patch wherever the light puts it, the
// blobs are the discs drawn, two clusters competing for a name get the names that fit them best
// together, clutter gets none, and the boxes classify every disc and no carpet.
#include "patlab/vision/thresholds_blobs.h"

#include <gtest/gtest.h>

#include <cmath>

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

TEST(ThresholdsBlobs, OnePatchColourWhereverTheLightPutsIt) {
  const std::array<uint8_t, 3> yellow = {200, 180, 40};
  const camera::Image image =
      Frame(240, 120, {{30, 60, 7, yellow}, {210, 60, 7, yellow}, {120, 30, 5, {40, 70, 200}}},
            0.35);
  BlobThresholdsOptions o;
  const NormalisedFrame f = NormaliseFrame(image, o);
  EXPECT_GT(f.carpet_pixels, 240 * 120 * 8 / 10);
  const std::vector<ColourBlob> blobs = FindColourBlobs(f, 0, o);
  ASSERT_EQ(blobs.size(), 3u);
  // In the order of their first pixel: the blue disc (row 25), then the two yellow ones.
  EXPECT_NEAR(blobs[0].x_px, 120.0, 0.3);
  EXPECT_NEAR(blobs[0].y_px, 30.0, 0.3);
  EXPECT_NEAR(static_cast<double>(blobs[0].pixels.size()), M_PI * 25, 12.0);
  EXPECT_NEAR(blobs[1].x_px, 30.0, 0.3);
  EXPECT_NEAR(blobs[2].x_px, 210.0, 0.3);
  // The two yellow discs are 2.9 times apart in light; normalised they are one colour, which
  // their raw colours are not.
  EXPECT_LT(DeltaE(blobs[1].lab, blobs[2].lab), 3.0);
  const std::array<double, 3> raw_left = SrgbToLab(yellow);
  const uint8_t* right = image.Row(60) + 3 * 210;
  const std::array<double, 3> raw_right = SrgbToLab({right[0], right[1], right[2]});
  EXPECT_GT(DeltaE(raw_left, raw_right), 15.0);
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
  for (int i = 0; i < 5; ++i) blobs.push_back({0, {}, 0, 0, salmon});
  blobs.push_back({0, {}, 0, 0, ball});
  blobs.push_back({0, {}, 0, 0, SrgbToLab({140, 50, 200})});  // purple: clutter here
  const std::vector<BlobCluster> clusters = NameBlobClusters({&pink, &orange}, o, &blobs);
  ASSERT_EQ(clusters.size(), 3u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(blobs[static_cast<size_t>(i)].name, 0) << i;
  EXPECT_EQ(blobs[5].name, 1);
  EXPECT_EQ(blobs[6].name, -1);
  EXPECT_EQ(clusters[static_cast<size_t>(blobs[0].cluster)].blobs, 5);
}

TEST(ThresholdsBlobs, AchromaticEntriesTakeLightnessNotHue) {
  const ColourVocabulary& vocabulary = io::DefaultColourVocabulary();
  const BlobThresholdsOptions o;
  const std::array<double, 3> grey_white = SrgbToLab({235, 238, 225});
  EXPECT_LT(NameCost(grey_white, *vocabulary.Find("white"), o), 1.0);
  EXPECT_GT(NameCost(grey_white, *vocabulary.Find("black"), o), 9.0);
  EXPECT_GT(NameCost(SrgbToLab({220, 200, 40}), *vocabulary.Find("white"), o), 9.0);
}

TEST(ThresholdsBlobs, BoxesClassifyEveryDiscAndNoCarpet) {
  const std::vector<Disc> discs = {
      {30, 30, 6, {235, 215, 45}},  {90, 30, 6, {35, 75, 210}},  {150, 30, 6, {240, 95, 185}},
      {30, 90, 6, {235, 215, 45}},  {90, 90, 6, {35, 75, 210}},  {150, 90, 6, {240, 95, 185}},
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

// The camera's noise on the carpet (vision/thresholds_noise_internal.h): NormaliseFrame counts
// each carpet pixel's residual from its light cell's median once, and MeasureCarpetNoise reads
// the box percentiles off the pooled counts. Checked against the definition computed by brute
// force: every residual collected, sorted, and indexed at floor(p last) and ceil(p last).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "patlab/vision/thresholds_blobs.h"
#include "patlab/vision/thresholds_noise_internal.h"

namespace patlab::vision {
namespace {

// A carpet (40, 100, 50) whose light rises left to right, patches of other colours, and Gaussian
// noise of `sigma` levels per channel.
camera::Image NoisyCarpet(int w, int h, double sigma, unsigned seed) {
  camera::Image image = camera::Image::Rgb(w, h);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::array<double, 3> c = {40, 100, 50};
      if ((x / 17 + y / 13) % 9 == 0) c = {230, 90, 180};  // patches, not carpet
      const double gain = 0.7 + 0.6 * x / (w - 1.0);
      uint8_t* p = image.Row(y) + 3 * x;
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<uint8_t>(std::clamp(std::lround(c[k] * gain + noise(rng)), 0L, 255L));
    }
  }
  return image;
}

// The definition: per light cell with at least an eighth of carpet, each carpet pixel's level
// less the cell's median (the middle element), pooled over the frames and sorted per channel.
std::array<std::vector<int>, 3> SortedResiduals(const std::vector<NormalisedFrame>& frames,
                                                int cell) {
  std::array<std::vector<int>, 3> residuals;
  for (const NormalisedFrame& f : frames) {
    for (int y0 = 0; y0 < f.height_px; y0 += cell) {
      for (int x0 = 0; x0 < f.width_px; x0 += cell) {
        std::vector<size_t> in_cell;
        for (int y = y0; y < std::min(f.height_px, y0 + cell); ++y)
          for (int x = x0; x < std::min(f.width_px, x0 + cell); ++x)
            if (f.carpet[static_cast<size_t>(y) * f.width_px + x] != 0)
              in_cell.push_back(static_cast<size_t>(y) * f.width_px + x);
        if (in_cell.empty() || in_cell.size() * 8 < static_cast<size_t>(cell * cell)) continue;
        for (int ch = 0; ch < 3; ++ch) {
          std::vector<int> values;
          for (const size_t i : in_cell) values.push_back(f.yuv[i][ch]);
          std::vector<int> sorted = values;
          std::sort(sorted.begin(), sorted.end());
          const int median = sorted[sorted.size() / 2];
          for (const int v : values) residuals[ch].push_back(v - median);
        }
      }
    }
  }
  for (std::vector<int>& r : residuals) std::sort(r.begin(), r.end());
  return residuals;
}

// The box percentiles: the sorted residuals at the ranks floor(lower / 100 last) and
// ceil(upper / 100 last).
internal::CameraNoise BruteForceNoise(const std::vector<NormalisedFrame>& frames,
                                      const BlobThresholdsOptions& o) {
  const std::array<std::vector<int>, 3> residuals = SortedResiduals(frames, o.light_cell_px);
  internal::CameraNoise noise;
  if (residuals[0].empty()) return noise;
  for (int ch = 0; ch < 3; ++ch) {
    const std::vector<int>& r = residuals[ch];
    const double last = static_cast<double>(r.size() - 1);
    noise.below[ch] = -r[static_cast<size_t>(std::floor(o.lower_percentile / 100.0 * last))];
    noise.above[ch] = r[static_cast<size_t>(std::ceil(o.upper_percentile / 100.0 * last))];
  }
  noise.pixels = static_cast<long>(residuals[0].size());
  return noise;
}

void ExpectSameNoise(const internal::CameraNoise& got, const internal::CameraNoise& want) {
  EXPECT_EQ(got.pixels, want.pixels);
  EXPECT_EQ(got.below, want.below);
  EXPECT_EQ(got.above, want.above);
}

TEST(CarpetNoise, TheCountedResidualsPercentilesAreTheSortedResiduals) {
  BlobThresholdsOptions o;
  const camera::Image a = NoisyCarpet(203, 151, 3.0, 1), b = NoisyCarpet(160, 97, 7.0, 2);
  const std::vector<NormalisedFrame> one = {NormaliseFrame(a, o)};
  const std::vector<NormalisedFrame> two = {NormaliseFrame(a, o), NormaliseFrame(b, o)};
  const internal::CameraNoise single = internal::MeasureCarpetNoise(one, o);
  ASSERT_GT(single.pixels, 20000);
  EXPECT_GT(single.above[0], 0);  // the noise is seen
  ExpectSameNoise(single, BruteForceNoise(one, o));
  // Pooled over two frames of other noise, and at other percentiles and cells.
  ExpectSameNoise(internal::MeasureCarpetNoise(two, o), BruteForceNoise(two, o));
  o.lower_percentile = 13.0;
  o.upper_percentile = 71.5;
  ExpectSameNoise(internal::MeasureCarpetNoise(two, o), BruteForceNoise(two, o));
  o.light_cell_px = 9;
  const std::vector<NormalisedFrame> fine = {NormaliseFrame(a, o), NormaliseFrame(b, o)};
  ExpectSameNoise(internal::MeasureCarpetNoise(fine, o), BruteForceNoise(fine, o));
}

TEST(CarpetNoise, APercentileAtTheStepBetweenTwoLevelsReadsTheRightOne) {
  // Most ranks share their residual with their neighbours; these fall on the rank k of the
  // first residual above v, so that one rank less or more reads another level.
  BlobThresholdsOptions o;
  const camera::Image a = NoisyCarpet(203, 151, 4.0, 4);
  const std::vector<NormalisedFrame> frames = {NormaliseFrame(a, o)};
  const std::vector<int> y = SortedResiduals(frames, o.light_cell_px)[0];
  const double last = static_cast<double>(y.size() - 1);
  int steps = 0;
  for (int v = -6; v <= 5; ++v) {
    const auto k = static_cast<double>(std::upper_bound(y.begin(), y.end(), v) - y.begin());
    if (k < 1 || k > last - 1) continue;
    ++steps;
    o.lower_percentile = std::min(49.9, 100.0 * (k + 0.5) / last);  // floor(p last) = k
    o.upper_percentile = std::max(50.1, 100.0 * (k - 0.5) / last);  // ceil(p last) = k
    ExpectSameNoise(internal::MeasureCarpetNoise(frames, o), BruteForceNoise(frames, o));
  }
  EXPECT_GE(steps, 8);
}

TEST(CarpetNoise, AFrameWithNoCellAnEighthCarpetMeasuresNoNoise) {
  // One light cell of 512 x 512 px, of which the 64 x 64 px frame covers under an eighth.
  BlobThresholdsOptions o;
  o.light_cell_px = 512;
  const camera::Image image = NoisyCarpet(64, 64, 3.0, 3);
  const std::vector<NormalisedFrame> frames = {NormaliseFrame(image, o)};
  const internal::CameraNoise noise = internal::MeasureCarpetNoise(frames, o);
  EXPECT_EQ(noise.pixels, 0);
  ExpectSameNoise(noise, BruteForceNoise(frames, o));
}

}  // namespace
}  // namespace patlab::vision

// The blob fit's boxes widened towards the camera's noise (thresholds_noise_internal.h).
#include <algorithm>
#include <cmath>

#include "patlab/vision/thresholds_noise_internal.h"

namespace patlab::vision::internal {

namespace {

int Median(std::vector<int>* values) {
  auto mid = values->begin() + static_cast<std::ptrdiff_t>(values->size() / 2);
  std::nth_element(values->begin(), mid, values->end());
  return *mid;
}

constexpr int kLevels = 256;  // a residual d is counted at index d + kLevels - 1

// The carpet's pixels of the cell at (x0, y0) about their median, per channel, counted into the
// frame's carpet_residual_counts, when at least an eighth of the cell is carpet.
void CountCellResiduals(int x0, int y0, int cell, NormalisedFrame* f) {
  std::vector<size_t> in_cell;
  for (int y = y0; y < std::min(f->height_px, y0 + cell); ++y) {
    for (int x = x0; x < std::min(f->width_px, x0 + cell); ++x) {
      const size_t i = static_cast<size_t>(y) * f->width_px + x;
      if (f->carpet[i] != 0) in_cell.push_back(i);
    }
  }
  if (in_cell.empty() || in_cell.size() * 8 < static_cast<size_t>(cell) * cell) return;
  std::vector<int> values;
  for (int ch = 0; ch < 3; ++ch) {
    values.clear();
    for (const size_t i : in_cell) values.push_back(f->yuv[i][ch]);
    const int median = Median(&values);
    for (const int v : values) ++f->carpet_residual_counts[ch][v - median + kLevels - 1];
  }
}

// The residual of the given rank (0: the lowest) among `counts`' residuals.
int ResidualOfRank(const std::vector<long>& counts, long rank) {
  long seen = 0;
  for (size_t d = 0; d < counts.size(); ++d) {
    seen += counts[d];
    if (seen > rank) return static_cast<int>(d) - (kLevels - 1);
  }
  return 0;
}

}  // namespace

void CountCarpetResiduals(int light_cell_px, NormalisedFrame* frame) {
  for (std::vector<long>& counts : frame->carpet_residual_counts) counts.assign(2 * kLevels - 1, 0);
  for (int y0 = 0; y0 < frame->height_px; y0 += light_cell_px)
    for (int x0 = 0; x0 < frame->width_px; x0 += light_cell_px)
      CountCellResiduals(x0, y0, light_cell_px, frame);
}

CameraNoise MeasureCarpetNoise(const std::vector<NormalisedFrame>& frames,
                               const BlobThresholdsOptions& options) {
  CameraNoise noise;
  std::array<std::vector<long>, 3> counts;
  for (std::vector<long>& c : counts) c.assign(2 * kLevels - 1, 0);
  for (const NormalisedFrame& f : frames)
    for (int ch = 0; ch < 3; ++ch)
      for (size_t d = 0; d < f.carpet_residual_counts[ch].size(); ++d)
        counts[ch][d] += f.carpet_residual_counts[ch][d];
  long pixels = 0;
  for (const long c : counts[0]) pixels += c;
  if (pixels == 0) return noise;
  // The box percentiles of the residuals sorted: ranks floor(p last) and ceil(p last).
  const double last = static_cast<double>(pixels - 1);
  for (int ch = 0; ch < 3; ++ch) {
    noise.below[ch] = -ResidualOfRank(
        counts[ch], static_cast<long>(std::floor(options.lower_percentile / 100.0 * last)));
    noise.above[ch] = ResidualOfRank(
        counts[ch], static_cast<long>(std::ceil(options.upper_percentile / 100.0 * last)));
  }
  noise.pixels = pixels;
  return noise;
}

std::array<int, 3> MedianColour(const std::vector<std::array<uint8_t, 3>>& pixels) {
  std::array<int, 3> median{};
  std::vector<int> values;
  for (int ch = 0; ch < 3; ++ch) {
    values.clear();
    for (const auto& p : pixels) values.push_back(p[ch]);
    median[ch] = Median(&values);
  }
  return median;
}

std::array<ChannelRange, 3> NoiseBox(const std::array<int, 3>& median, const CameraNoise& noise,
                                     const BlobThresholdsOptions& options) {
  std::array<ChannelRange, 3> box{};
  for (int ch = 0; ch < 3; ++ch) {
    box[ch] = {std::clamp(median[ch] - noise.below[ch] - options.margin_levels, 0, 255),
               std::clamp(median[ch] + noise.above[ch] + options.margin_levels, 0, 255)};
  }
  return box;
}

std::array<int, 3> WidenToNoise(const std::array<int, 3>& median, const CameraNoise& noise,
                                double weight, const BlobThresholdsOptions& options,
                                std::array<ChannelRange, 3>* box) {
  std::array<int, 3> widened{};
  if (noise.pixels == 0) return widened;
  const std::array<ChannelRange, 3> noise_box = NoiseBox(median, noise, options);
  for (int ch = 0; ch < 3; ++ch) {
    ChannelRange& r = (*box)[ch];
    const int lo =
        std::min(r.lo, static_cast<int>(std::floor(r.lo + weight * (noise_box[ch].lo - r.lo))));
    const int hi =
        std::max(r.hi, static_cast<int>(std::ceil(r.hi + weight * (noise_box[ch].hi - r.hi))));
    widened[ch] = (r.lo - lo) + (hi - r.hi);
    r.lo = lo, r.hi = hi;
  }
  return widened;
}

}  // namespace patlab::vision::internal

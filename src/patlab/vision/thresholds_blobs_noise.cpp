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

// The carpet's pixels of the cell at (x0, y0) about their median, per channel, added to
// `residuals`, when at least an eighth of the cell is carpet.
void AddCellResiduals(const NormalisedFrame& f, int x0, int y0, int cell,
                      std::array<std::vector<int>, 3>* residuals) {
  std::vector<size_t> in_cell;
  for (int y = y0; y < std::min(f.height_px, y0 + cell); ++y) {
    for (int x = x0; x < std::min(f.width_px, x0 + cell); ++x) {
      const size_t i = static_cast<size_t>(y) * f.width_px + x;
      if (f.carpet[i] != 0) in_cell.push_back(i);
    }
  }
  if (in_cell.empty() || in_cell.size() * 8 < static_cast<size_t>(cell) * cell) return;
  std::vector<int> values;
  for (int ch = 0; ch < 3; ++ch) {
    values.clear();
    for (const size_t i : in_cell) values.push_back(f.yuv[i][ch]);
    const int median = Median(&values);
    for (const int v : values) (*residuals)[ch].push_back(v - median);
  }
}

}  // namespace

CameraNoise MeasureCarpetNoise(const std::vector<NormalisedFrame>& frames,
                               const BlobThresholdsOptions& options) {
  CameraNoise noise;
  const int cell = options.light_cell_px;
  std::array<std::vector<int>, 3> residuals;
  for (const NormalisedFrame& f : frames) {
    for (int y0 = 0; y0 < f.height_px; y0 += cell)
      for (int x0 = 0; x0 < f.width_px; x0 += cell) AddCellResiduals(f, x0, y0, cell, &residuals);
  }
  if (residuals[0].empty()) return noise;
  for (int ch = 0; ch < 3; ++ch) {
    std::vector<int>& r = residuals[ch];
    std::sort(r.begin(), r.end());
    const double last = static_cast<double>(r.size() - 1);
    noise.below[ch] = -r[static_cast<size_t>(std::floor(options.lower_percentile / 100.0 * last))];
    noise.above[ch] = r[static_cast<size_t>(std::ceil(options.upper_percentile / 100.0 * last))];
  }
  noise.pixels = static_cast<long>(residuals[0].size());
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

// Colour classes from patch blobs (thresholds_blobs.h), stages 1 and 2: the light-normalised
// frame and its blobs. Naming and boxes: thresholds_blobs_name.cpp.
#include "patlab/vision/thresholds_blobs.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "patlab/core/portable_math.h"
#include "patlab/vision/thresholds_noise_internal.h"
#include "patlab/vision/thresholds_options_internal.h"

namespace patlab::vision {

std::vector<OptionsProblem> Check(const BlobThresholdsOptions& o) {
  OptionsChecker check;
  check
      .Require("min_blob_area_px", o.min_blob_area_px,
               o.min_blob_area_px >= 1.0 && o.min_blob_area_px <= 1e6, "in [1, 1e6]")
      .Require("max_blob_area_px", o.max_blob_area_px, o.max_blob_area_px >= o.min_blob_area_px,
               ">= min_blob_area_px")
      .Require("min_blob_sigma_px", o.min_blob_sigma_px,
               o.min_blob_sigma_px >= 0.0 && o.min_blob_sigma_px <= 1000.0, "in [0, 1000]")
      .IntegerInRange("light_cell_px", o.light_cell_px, 4, 512)
      .Require("max_light_gain", o.max_light_gain,
               o.max_light_gain >= 1.0 && o.max_light_gain <= 16.0, "in [1, 16]")
      .Require("standout_delta_e", o.standout_delta_e,
               o.standout_delta_e > 0.0 && o.standout_delta_e <= 200.0, "in (0, 200]")
      .Require("segment_k", o.segment_k, o.segment_k > 0.0 && o.segment_k <= 10000.0,
               "in (0, 10000]")
      .Require("cluster_distance", o.cluster_distance,
               o.cluster_distance > 0.0 && o.cluster_distance <= 200.0, "in (0, 200]")
      .Require("lightness_weight", o.lightness_weight,
               o.lightness_weight > 0.0 && o.lightness_weight <= 1.0, "in (0, 1]")
      .Require("hue_spread_deg", o.hue_spread_deg,
               o.hue_spread_deg > 0.0 && o.hue_spread_deg <= 180.0, "in (0, 180]")
      .Require("lightness_spread", o.lightness_spread,
               o.lightness_spread > 0.0 && o.lightness_spread <= 100.0, "in (0, 100]")
      .Require("chroma_spread", o.chroma_spread, o.chroma_spread > 0.0 && o.chroma_spread <= 10.0,
               "in (0, 10]")
      .Require("achromatic_chroma", o.achromatic_chroma,
               o.achromatic_chroma > 0.0 && o.achromatic_chroma <= 100.0, "in (0, 100]")
      .Require("max_name_cost", o.max_name_cost, o.max_name_cost > 0.0 && o.max_name_cost <= 1000.0,
               "in (0, 1000]");
  internal::CheckBoxOptions(check, o).Require("negative_weight", o.negative_weight,
                                              o.negative_weight > 0.0 && o.negative_weight <= 100.0,
                                              "in (0, 100]");
  return check.Take();
}

void Validate(const BlobThresholdsOptions& options) { ThrowFirstProblem(Check(options)); }

namespace {

// sRGB level -> linear intensity, once.
const std::array<double, 256>& LinearTable() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = c <= 0.04045 ? c / 12.92 : pmath::Exp(2.4 * pmath::Log((c + 0.055) / 1.055));
    }
    return t;
  }();
  return table;
}

double LabF(double t) {
  return t > 0.008856 ? pmath::Exp(pmath::Log(t) / 3.0) : 7.787 * t + 16.0 / 116.0;
}

// CIELAB (D65) of linear RGB.
std::array<double, 3> LinearToLab(double r, double g, double b) {
  const double x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
  const double fx = LabF(x), fy = LabF(y), fz = LabF(z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double Luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// Each pixel's RGB and YUV, whatever the frame's format.
void ReadPixels(const camera::Image& image, std::vector<std::array<uint8_t, 3>>* rgb,
                std::vector<std::array<uint8_t, 3>>* yuv) {
  const size_t n = static_cast<size_t>(image.width_px) * image.height_px;
  rgb->resize(n), yuv->resize(n);
  for (int y = 0; y < image.height_px; ++y) {
    const uint8_t* row = image.Row(y);
    for (int x = 0; x < image.width_px; ++x) {
      const size_t i = static_cast<size_t>(y) * image.width_px + x;
      int c[3], d[3];
      if (image.format == camera::PixelFormat::kRgb8) {
        for (int k = 0; k < 3; ++k) c[k] = row[3 * x + k];
        camera::RgbToYuv(c[0], c[1], c[2], &d[0], &d[1], &d[2]);
      } else {
        const uint8_t* pair = row + 4 * (x / 2);
        d[0] = pair[1 + 2 * (x % 2)], d[1] = pair[0], d[2] = pair[2];
        camera::YuvToRgb(d[0], d[1], d[2], &c[0], &c[1], &c[2]);
      }
      for (int k = 0; k < 3; ++k) {
        (*rgb)[i][k] = static_cast<uint8_t>(c[k]), (*yuv)[i][k] = static_cast<uint8_t>(d[k]);
      }
    }
  }
}

// The carpet: the fullest cell of a YUV histogram (16 luma x 8 chroma levels), refined to the
// pixels whose chroma lies within 2.5 spreads (at least 6 levels) of its mean and whose luma is
// within a factor 3 of its mean (the light varies over the field; the chroma much less).
std::vector<uint8_t> FindCarpetPixels(const std::vector<std::array<uint8_t, 3>>& yuv) {
  std::vector<long> cells(16 * 32 * 32, 0);
  for (const auto& p : yuv) ++cells[(p[0] >> 4) * 1024 + (p[1] >> 3) * 32 + (p[2] >> 3)];
  const int mode = static_cast<int>(std::max_element(cells.begin(), cells.end()) - cells.begin());
  double my = (mode / 1024) * 16 + 7.5, mu = ((mode / 32) % 32) * 8 + 3.5,
         mv = (mode % 32) * 8 + 3.5;
  double su = 6.0, sv = 6.0;
  std::vector<uint8_t> carpet(yuv.size(), 0);
  for (int round = 0; round < 4; ++round) {
    double n = 0, sy = 0, s_u = 0, s_v = 0, s_uu = 0, s_vv = 0;
    for (size_t i = 0; i < yuv.size(); ++i) {
      const auto& p = yuv[i];
      const double du = p[1] - mu, dv = p[2] - mv, y = std::max<double>(p[0], 1.0);
      const bool in = std::abs(du) <= std::max(6.0, 2.5 * su) &&
                      std::abs(dv) <= std::max(6.0, 2.5 * sv) && y >= my / 3.0 && y <= my * 3.0;
      carpet[i] = in ? 1 : 0;
      if (!in) continue;
      n += 1, sy += p[0], s_u += p[1], s_v += p[2];
      s_uu += 1.0 * p[1] * p[1], s_vv += 1.0 * p[2] * p[2];
    }
    if (n < 1) break;
    my = std::max(sy / n, 2.0), mu = s_u / n, mv = s_v / n;
    su = std::sqrt(std::max(0.0, s_uu / n - mu * mu));
    sv = std::sqrt(std::max(0.0, s_vv / n - mv * mv));
  }
  return carpet;
}

// The carpet's linear luminance per cell (median of its pixels there; cells with too few carpet
// pixels filled from their neighbours), smoothed over 3 x 3 cells.
struct LightGrid {
  int cols = 0, rows = 0, cell = 1;
  std::vector<double> value;
  double At(double x, double y) const;
};

double LightGrid::At(double x, double y) const {
  const double gx = std::clamp(x / cell - 0.5, 0.0, cols - 1.0);
  const double gy = std::clamp(y / cell - 0.5, 0.0, rows - 1.0);
  const int x0 = std::min(static_cast<int>(gx), cols - 1),
            y0 = std::min(static_cast<int>(gy), rows - 1);
  const int x1 = std::min(x0 + 1, cols - 1), y1 = std::min(y0 + 1, rows - 1);
  const double fx = gx - x0, fy = gy - y0;
  const auto v = [&](int c, int r) { return value[static_cast<size_t>(r) * cols + c]; };
  return (1 - fy) * ((1 - fx) * v(x0, y0) + fx * v(x1, y0)) +
         fy * ((1 - fx) * v(x0, y1) + fx * v(x1, y1));
}

// Cells without a value (negative) take the mean of their valued 8-neighbours, round by round.
void FillEmptyCells(int cols, int rows, std::vector<double>* value) {
  for (int round = 0; round < cols + rows; ++round) {
    std::vector<double> next = *value;
    bool empty = false;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if ((*value)[static_cast<size_t>(r) * cols + c] >= 0.0) continue;
        double s = 0, n = 0;
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
            const double v = (*value)[static_cast<size_t>(rr) * cols + cc];
            if (v >= 0.0) s += v, n += 1;
          }
        }
        if (n > 0) {
          next[static_cast<size_t>(r) * cols + c] = s / n;
        } else {
          empty = true;
        }
      }
    }
    *value = std::move(next);
    if (!empty) return;
  }
}

LightGrid MeasureLight(int width, int height, int cell, const std::vector<double>& luminance,
                       const std::vector<uint8_t>& carpet, double fallback) {
  LightGrid g;
  g.cell = cell;
  g.cols = (width + cell - 1) / cell, g.rows = (height + cell - 1) / cell;
  g.value.assign(static_cast<size_t>(g.cols) * g.rows, -1.0);
  std::vector<double> samples;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      samples.clear();
      for (int y = r * cell; y < std::min(height, (r + 1) * cell); ++y) {
        for (int x = c * cell; x < std::min(width, (c + 1) * cell); ++x) {
          const size_t i = static_cast<size_t>(y) * width + x;
          if (carpet[i] != 0) samples.push_back(luminance[i]);
        }
      }
      if (samples.size() * 8 < static_cast<size_t>(cell) * cell) continue;
      auto mid = samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2);
      std::nth_element(samples.begin(), mid, samples.end());
      g.value[static_cast<size_t>(r) * g.cols + c] = *mid;
    }
  }
  FillEmptyCells(g.cols, g.rows, &g.value);
  for (double& v : g.value) v = v >= 0.0 ? v : fallback;
  std::vector<double> smooth(g.value.size());
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      double s = 0, n = 0;
      for (int rr = std::max(0, r - 1); rr <= std::min(g.rows - 1, r + 1); ++rr)
        for (int cc = std::max(0, c - 1); cc <= std::min(g.cols - 1, c + 1); ++cc)
          s += g.value[static_cast<size_t>(rr) * g.cols + cc], n += 1;
      smooth[static_cast<size_t>(r) * g.cols + c] = s / n;
    }
  }
  g.value = std::move(smooth);
  return g;
}

}  // namespace

std::array<double, 3> SrgbToLab(const std::array<uint8_t, 3>& rgb) {
  const auto& lin = LinearTable();
  return LinearToLab(lin[rgb[0]], lin[rgb[1]], lin[rgb[2]]);
}

NormalisedFrame NormaliseFrame(const camera::Image& image, const BlobThresholdsOptions& options) {
  NormalisedFrame f;
  f.width_px = image.width_px, f.height_px = image.height_px;
  std::vector<std::array<uint8_t, 3>> rgb;
  ReadPixels(image, &rgb, &f.yuv);
  const auto& lin = LinearTable();
  const size_t n = rgb.size();
  std::vector<double> luminance(n);
  for (size_t i = 0; i < n; ++i)
    luminance[i] = Luminance(lin[rgb[i][0]], lin[rgb[i][1]], lin[rgb[i][2]]);
  f.carpet = FindCarpetPixels(f.yuv);
  std::vector<double> on_carpet;
  for (size_t i = 0; i < n; ++i)
    if (f.carpet[i] != 0) on_carpet.push_back(luminance[i]);
  double global = 0.05;
  if (!on_carpet.empty()) {
    auto mid = on_carpet.begin() + static_cast<std::ptrdiff_t>(on_carpet.size() / 2);
    std::nth_element(on_carpet.begin(), mid, on_carpet.end());
    global = std::max(*mid, 1e-4);
  }
  const LightGrid light =
      MeasureLight(f.width_px, f.height_px, options.light_cell_px, luminance, f.carpet, global);
  // Each pixel's colour, and its light-normalised colour for the stand-out test.
  f.lab.resize(n);
  std::vector<std::array<double, 3>> scaled(n);
  std::array<double, 3> lab_sum{}, yuv_sum{};
  for (size_t i = 0; i < n; ++i) {
    const int x = static_cast<int>(i % f.width_px), y = static_cast<int>(i / f.width_px);
    const double gain = std::clamp(global / std::max(light.At(x, y), 1e-4),
                                   1.0 / options.max_light_gain, options.max_light_gain);
    const double r = lin[rgb[i][0]], g = lin[rgb[i][1]], b = lin[rgb[i][2]];
    const auto lab = LinearToLab(r, g, b);
    for (int k = 0; k < 3; ++k) f.lab[i][k] = static_cast<float>(lab[k]);
    scaled[i] = LinearToLab(gain * r, gain * g, gain * b);
    if (f.carpet[i] == 0) continue;
    ++f.carpet_pixels;
    for (int k = 0; k < 3; ++k) lab_sum[k] += scaled[i][k], yuv_sum[k] += f.yuv[i][k];
  }
  for (int k = 0; k < 3; ++k) {
    f.carpet_lab[k] = f.carpet_pixels > 0 ? lab_sum[k] / f.carpet_pixels : 0.0;
    f.carpet_yuv[k] = f.carpet_pixels > 0 ? yuv_sum[k] / f.carpet_pixels : 0.0;
  }
  f.standout_delta_e2.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      f.standout_delta_e2[i] += (scaled[i][k] - f.carpet_lab[k]) * (scaled[i][k] - f.carpet_lab[k]);
  internal::CountCarpetResiduals(options.light_cell_px, &f);
  return f;
}

namespace {

double DeltaE(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  const double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

int Root(std::vector<int>* parent, int i) {
  while ((*parent)[i] != i) i = (*parent)[i] = (*parent)[(*parent)[i]];
  return i;
}

// Felzenszwalb-Huttenlocher over the candidate pixels: every pixel's component root.
std::vector<int> Segment(const NormalisedFrame& f, const std::vector<uint8_t>& candidate,
                         double k) {
  const int w = f.width_px, h = f.height_px;
  struct Edge {
    int key, a, b;
  };
  std::vector<Edge> edges;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if (candidate[i] == 0) continue;
      for (const int j : {x + 1 < w ? i + 1 : -1, y + 1 < h ? i + w : -1}) {
        if (j < 0 || candidate[j] == 0) continue;
        edges.push_back({static_cast<int>(std::lround(16.0 * DeltaE(f.lab[i], f.lab[j]))), i, j});
      }
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.key != b.key ? a.key < b.key : (a.a != b.a ? a.a < b.a : a.b < b.b);
  });
  std::vector<int> parent(static_cast<size_t>(w) * h);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> size(parent.size(), 1);
  std::vector<double> internal(parent.size(), 0.0);
  for (const Edge& e : edges) {
    const int a = Root(&parent, e.a), b = Root(&parent, e.b);
    if (a == b) continue;
    const double weight = e.key / 16.0;
    if (weight > std::min(internal[a] + k / size[a], internal[b] + k / size[b])) continue;
    const int keep = size[a] >= size[b] ? a : b, gone = keep == a ? b : a;
    parent[gone] = keep, size[keep] += size[gone], internal[keep] = weight;
  }
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = Root(&parent, static_cast<int>(i));
  return parent;
}

double Median(std::vector<double>* v) {
  auto mid = v->begin() + static_cast<std::ptrdiff_t>(v->size() / 2);
  std::nth_element(v->begin(), mid, v->end());
  return *mid;
}

// The smaller principal axis's standard deviation of the pixels about their centroid.
double MinorSigma(const std::vector<int>& pixels, int width, double cx, double cy) {
  double sxx = 0, syy = 0, sxy = 0;
  for (const int i : pixels) {
    const double dx = i % width - cx, dy = i / width - cy;
    sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
  }
  const double n = static_cast<double>(pixels.size());
  sxx /= n, syy /= n, sxy /= n;
  // Pixels are squares: each adds 1/12 px^2 per axis.
  const double mean = 0.5 * (sxx + syy) + 1.0 / 12.0;
  const double half = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  return std::sqrt(std::max(0.0, mean - half));
}

}  // namespace

std::vector<ColourBlob> FindColourBlobs(const NormalisedFrame& f, int frame_index,
                                        const BlobThresholdsOptions& options,
                                        std::vector<uint8_t>* oversize,
                                        std::vector<std::vector<int>>* narrow) {
  const size_t n = f.lab.size();
  if (oversize != nullptr) oversize->assign(n, 0);
  if (narrow != nullptr) narrow->clear();
  const double limit2 = options.standout_delta_e * options.standout_delta_e;
  std::vector<uint8_t> candidate(n);
  for (size_t i = 0; i < n; ++i) candidate[i] = f.standout_delta_e2[i] > limit2 ? 1 : 0;
  const std::vector<int> root = Segment(f, candidate, options.segment_k);
  // Components in the order of their first pixel.
  std::vector<int> slot(n, -1);
  std::vector<std::vector<int>> members;
  for (size_t i = 0; i < n; ++i) {
    if (candidate[i] == 0) continue;
    const auto r = static_cast<size_t>(root[i]);
    if (slot[r] < 0) slot[r] = static_cast<int>(members.size()), members.emplace_back();
    members[static_cast<size_t>(slot[r])].push_back(static_cast<int>(i));
  }
  std::vector<ColourBlob> blobs;
  std::vector<double> channel;
  for (std::vector<int>& m : members) {
    const double area = static_cast<double>(m.size());
    if (oversize != nullptr && area > options.max_blob_area_px)
      for (const int i : m) (*oversize)[static_cast<size_t>(i)] = 1;
    if (area < options.min_blob_area_px || area > options.max_blob_area_px) continue;
    ColourBlob b;
    b.frame = frame_index;
    for (const int i : m) b.x_px += i % f.width_px, b.y_px += i / f.width_px;
    b.x_px /= area, b.y_px /= area;
    b.sigma_minor_px = MinorSigma(m, f.width_px, b.x_px, b.y_px);
    if (b.sigma_minor_px < options.min_blob_sigma_px) {
      if (narrow != nullptr) narrow->push_back(std::move(m));
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      channel.clear();
      for (const int i : m) channel.push_back(f.lab[static_cast<size_t>(i)][k]);
      b.lab[k] = Median(&channel);
    }
    b.pixels = std::move(m);
    blobs.push_back(std::move(b));
  }
  return blobs;
}

}  // namespace patlab::vision

#include "patlab/vision/segment.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cstring>

#include "patlab/core/error.h"

namespace patlab::vision {

std::vector<OptionsProblem> Check(const SegmenterOptions& options) {
  OptionsChecker check;
  check.Require("min_area_px", options.min_area_px, options.min_area_px >= 1, "an integer >= 1")
      .InRange("min_fill", options.min_fill, 0.0, 1.0);
  return check.Take();
}

void Validate(const SegmenterOptions& options) { ThrowFirstProblem(Check(options)); }

Segmenter::Segmenter(const Thresholds& thresholds, const SegmenterOptions& options)
    : lut_(thresholds), options_(options) {
  Validate(options);
  for (const ColorClass& c : thresholds.classes) {
    min_area_px_.push_back(c.min_area_px > 0 ? c.min_area_px : options.min_area_px);
    max_area_px_.push_back(c.max_area_px > 0 ? c.max_area_px : INT_MAX);
    ClassBox box{};
    for (int ch = 0; ch < 3; ++ch) {
      box.lo[ch] = static_cast<uint8_t>(c.range[ch].lo);
      box.width[ch] = static_cast<uint8_t>(c.range[ch].hi - c.range[ch].lo);
    }
    boxes_.push_back(box);
  }
}

namespace {

inline uint8_t Clamp255(int v) { return static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v)); }

// The loops below are plain element-wise loops over one row, which GCC vectorises (-O3); each
// repeats image.h's RgbToYuv / YuvToRgb arithmetic exactly, lane by lane.

void SplitRgb(const uint8_t* __restrict in, int n, uint8_t* __restrict c0, uint8_t* __restrict c1,
              uint8_t* __restrict c2) {
  for (int x = 0; x < n; ++x) {
    c0[x] = in[3 * x];
    c1[x] = in[3 * x + 1];
    c2[x] = in[3 * x + 2];
  }
}

// RgbToYuv in 16-bit lanes (twice the pixels per vector of 32-bit ones), exactly:
//   Y = (77r + 150g + 29b + 128) >> 8, at most 65408: no clamp needed.
//   U = floor((128b + 128 - 43r - 85g) / 256) + 128 = floor(P / 256), P = X - S with
//       X = 128b + 32896 and S = 43r + 85g; P reaches 65536, so halve it first:
//       floor(P / 2) = X / 2 - ceil(S / 2) = (64b + 16448) - ((S + 1) >> 1), in 128..32768,
//       and floor(P / 256) = floor(P / 2) >> 7, in 1..256, clamped to 255.
//   V the same with X = 128r + 32896, S = 107g + 21b.
void RgbRowToYuv(const uint8_t* __restrict in, int n, uint8_t* __restrict c0,
                 uint8_t* __restrict c1, uint8_t* __restrict c2) {
  for (int x = 0; x < n; ++x) {
    const uint16_t r = in[3 * x], g = in[3 * x + 1], b = in[3 * x + 2];
    const uint16_t y = static_cast<uint16_t>(77 * r + 150 * g + 29 * b + 128);
    const uint16_t su = static_cast<uint16_t>((43 * r + 85 * g + 1) >> 1);
    const uint16_t sv = static_cast<uint16_t>((107 * g + 21 * b + 1) >> 1);
    const uint16_t u = static_cast<uint16_t>((64 * b + 16448 - su) >> 7);
    const uint16_t v = static_cast<uint16_t>((64 * r + 16448 - sv) >> 7);
    c0[x] = static_cast<uint8_t>(y >> 8);
    c1[x] = static_cast<uint8_t>(u < 255 ? u : 255);
    c2[x] = static_cast<uint8_t>(v < 255 ? v : 255);
  }
}

// UYVY: U and V are shared by each pixel pair; n_pairs = width / 2.
void SplitUyvy(const uint8_t* __restrict in, int n_pairs, uint8_t* __restrict c0,
               uint8_t* __restrict c1, uint8_t* __restrict c2) {
  for (int p = 0; p < n_pairs; ++p) {
    const uint8_t u = in[4 * p], v = in[4 * p + 2];
    c0[2 * p] = in[4 * p + 1];
    c0[2 * p + 1] = in[4 * p + 3];
    c1[2 * p] = u;
    c1[2 * p + 1] = u;
    c2[2 * p] = v;
    c2[2 * p + 1] = v;
  }
}

void UyvyRowToRgb(const uint8_t* __restrict in, int n_pairs, uint8_t* __restrict c0,
                  uint8_t* __restrict c1, uint8_t* __restrict c2) {
  for (int p = 0; p < n_pairs; ++p) {
    const int d = in[4 * p] - 128, e = in[4 * p + 2] - 128;
    const int dr = (359 * e + 128) >> 8, dg = (88 * d + 183 * e + 128) >> 8;
    const int db = (454 * d + 128) >> 8;
    for (int k = 0; k < 2; ++k) {
      const int y = in[4 * p + 1 + 2 * k];
      c0[2 * p + k] = Clamp255(y + dr);
      c1[2 * p + k] = Clamp255(y - dg);
      c2[2 * p + k] = Clamp255(y + db);
    }
  }
}

// out[x] = label where (c0, c1, c2)[x] lies in the box, else unchanged. Branch-free byte
// compares: v is in lo..lo + width exactly when uint8(v - lo) <= width.
void PaintBox(const uint8_t* __restrict c0, const uint8_t* __restrict c1,
              const uint8_t* __restrict c2, int n, const std::array<uint8_t, 3>& lo,
              const std::array<uint8_t, 3>& width, uint8_t label, uint8_t* __restrict out) {
  const uint8_t l0 = lo[0], l1 = lo[1], l2 = lo[2];
  const uint8_t w0 = width[0], w1 = width[1], w2 = width[2];
  for (int x = 0; x < n; ++x) {
    const bool inside = (static_cast<uint8_t>(c0[x] - l0) <= w0) &
                        (static_cast<uint8_t>(c1[x] - l1) <= w1) &
                        (static_cast<uint8_t>(c2[x] - l2) <= w2);
    out[x] = inside ? label : out[x];
  }
}

}  // namespace

void Segmenter::Classify(const Image& image) {
  PATLAB_CHECK(image.width_px > 0 && image.height_px > 0);
  width_ = image.width_px;
  height_ = image.height_px;
  const int w = width_;
  class_image_.resize(static_cast<size_t>(w) * height_);
  planes_.resize(3 * static_cast<size_t>(w));
  uint8_t* c0 = planes_.data();
  uint8_t* c1 = c0 + w;
  uint8_t* c2 = c1 + w;
  const bool yuv_lut = lut_.space() == ColorSpace::kYuv;
  const bool rgb = image.format == PixelFormat::kRgb8;
  if (!rgb && w % 2 != 0) {
    // UYVY frames have even widths (frame_io checks); a last lone pixel would have no U, V.
    c0[w - 1] = c1[w - 1] = c2[w - 1] = 0;
  }
  const int num_boxes = static_cast<int>(boxes_.size());
  for (int y = 0; y < height_; ++y) {
    const uint8_t* in = image.Row(y);
    uint8_t* out = class_image_.data() + static_cast<size_t>(y) * w;
    if (rgb) {
      (yuv_lut ? RgbRowToYuv : SplitRgb)(in, w, c0, c1, c2);
    } else {
      (yuv_lut ? SplitUyvy : UyvyRowToRgb)(in, w / 2, c0, c1, c2);
    }
    std::memset(out, 0, static_cast<size_t>(w));
    // Last class first: a pixel in several boxes ends with the first listed (ColorLut's rule).
    for (int k = num_boxes - 1; k >= 0; --k) {
      const ClassBox& box = boxes_[static_cast<size_t>(k)];
      PaintBox(c0, c1, c2, w, box.lo, box.width, static_cast<uint8_t>(k + 1), out);
    }
    if (!rgb && w % 2 != 0) out[w - 1] = 0;
  }
}

namespace {

inline int32_t FindRoot(std::vector<Run>& runs, int32_t i) {
  while (runs[i].parent != i) {
    runs[i].parent = runs[runs[i].parent].parent;  // path halving
    i = runs[i].parent;
  }
  return i;
}

// Links the later root under the earlier one, so a run's parent always has a smaller index;
// ExtractRegions relies on that to resolve every label in one forward pass.
inline void Unite(std::vector<Run>& runs, int32_t a, int32_t b) {
  const int32_t ra = FindRoot(runs, a), rb = FindRoot(runs, b);
  if (ra < rb) {
    runs[rb].parent = ra;
  } else if (rb < ra) {
    runs[ra].parent = rb;
  }
}

}  // namespace

void Segmenter::EncodeRuns() {
  runs_.clear();
  int32_t prev_begin = 0, prev_end = 0;
  const int w = width_;
  for (int y = 0; y < height_; ++y) {
    const uint8_t* row = class_image_.data() + static_cast<size_t>(y) * w;
    const int32_t cur_begin = static_cast<int32_t>(runs_.size());
    int x = 0;
    while (x < w) {
      // Most pixels belong to no class: skip them eight at a time.
      while (x + 8 <= w) {
        uint64_t word;
        std::memcpy(&word, row + x, 8);
        if (word != 0) break;
        x += 8;
      }
      while (x < w && row[x] == 0) ++x;
      if (x >= w) break;
      const uint8_t c = row[x];
      const int start = x;
      while (x < w && row[x] == c) ++x;
      const int32_t index = static_cast<int32_t>(runs_.size());
      runs_.push_back(Run{start, x - 1, y, index, c - 1});
    }
    const int32_t cur_end = static_cast<int32_t>(runs_.size());
    // Join overlapping runs of the same class on the previous row (two-pointer sweep).
    int32_t i = prev_begin, j = cur_begin;
    while (i < prev_end && j < cur_end) {
      const Run& a = runs_[i];
      const Run& b = runs_[j];
      if (a.x_end < b.x_begin) {
        ++i;
        continue;
      }
      if (b.x_end < a.x_begin) {
        ++j;
        continue;
      }
      if (a.colour == b.colour) Unite(runs_, i, j);
      if (a.x_end < b.x_end) {
        ++i;
      } else if (b.x_end < a.x_end) {
        ++j;
      } else {
        ++i;
        ++j;
      }
    }
    prev_begin = cur_begin;
    prev_end = cur_end;
  }
}

void Segmenter::ExtractRegions() {
  const int32_t n = static_cast<int32_t>(runs_.size());
  label_.resize(static_cast<size_t>(n));
  accumulators_.clear();
  for (int32_t i = 0; i < n; ++i) {
    Run& run = runs_[i];
    if (run.parent == i) {
      label_[i] = static_cast<int32_t>(accumulators_.size());
      accumulators_.push_back(Accumulator{0, 0, 0, INT_MAX, INT_MAX, INT_MIN, INT_MIN, run.colour});
    } else {
      run.parent = runs_[run.parent].parent;  // the parent is earlier, hence already a root
      label_[i] = label_[run.parent];
    }
    Accumulator& acc = accumulators_[label_[i]];
    const int64_t width = run.x_end - run.x_begin + 1;
    acc.area += width;
    // Sum of x over x_begin..x_end; the product is always even.
    acc.sum_x += (static_cast<int64_t>(run.x_begin) + run.x_end) * width / 2;
    acc.sum_y += static_cast<int64_t>(run.y) * width;
    acc.x_min = std::min(acc.x_min, static_cast<int>(run.x_begin));
    acc.x_max = std::max(acc.x_max, static_cast<int>(run.x_end));
    acc.y_min = std::min(acc.y_min, static_cast<int>(run.y));
    acc.y_max = std::max(acc.y_max, static_cast<int>(run.y));
  }
  num_raw_regions_ = static_cast<int>(accumulators_.size());
  regions_.clear();
  for (const Accumulator& acc : accumulators_) {
    if (acc.area < min_area_px_[acc.colour] || acc.area > max_area_px_[acc.colour]) continue;
    Region r;
    r.colour = acc.colour;
    r.area_px = static_cast<int>(acc.area);
    r.x_min = acc.x_min;
    r.y_min = acc.y_min;
    r.x_max = acc.x_max;
    r.y_max = acc.y_max;
    r.centroid_px =
        Vec2(static_cast<double>(acc.sum_x) / acc.area, static_cast<double>(acc.sum_y) / acc.area);
    if (r.Fill() < options_.min_fill) continue;
    regions_.push_back(r);
  }
  std::sort(regions_.begin(), regions_.end(), [](const Region& a, const Region& b) {
    if (a.colour != b.colour) return a.colour < b.colour;
    if (a.area_px != b.area_px) return a.area_px > b.area_px;
    if (a.centroid_px.y() != b.centroid_px.y()) return a.centroid_px.y() < b.centroid_px.y();
    return a.centroid_px.x() < b.centroid_px.x();
  });
  class_begin_.assign(static_cast<size_t>(lut_.num_classes()) + 1, 0);
  for (const Region& r : regions_) ++class_begin_[r.colour + 1];
  for (int k = 0; k < lut_.num_classes(); ++k) class_begin_[k + 1] += class_begin_[k];
}

std::span<const Region> Segmenter::RegionsOf(int colour) const {
  PATLAB_CHECK(colour >= 0 && colour < lut_.num_classes());
  if (class_begin_.empty()) return {};
  return std::span<const Region>(regions_.data() + class_begin_[colour],
                                 regions_.data() + class_begin_[colour + 1]);
}

}  // namespace patlab::vision

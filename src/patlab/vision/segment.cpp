#include "patlab/vision/segment.h"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cstring>

#if defined(__AVX512VBMI__) && defined(__AVX512BW__)
#include <immintrin.h>
#define PATLAB_SEGMENT_AVX512 1
#endif

#include "patlab/core/error.h"
#include "patlab/vision/segment_internal.h"

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
#ifdef PATLAB_SEGMENT_AVX512
  use_tables_ = boxes_.size() <= 8;
#endif
  if (!use_tables_) return;
  for (int ch = 0; ch < 3; ++ch) {  // ColorLut's masks, which fit a byte
    for (int v = 0; v < 256; ++v) channel_bits_[ch][v] = static_cast<uint8_t>(lut_.table(ch)[v]);
  }
  for (int bits = 1; bits < 256; ++bits) {
    first_class_[bits] = static_cast<uint8_t>(std::countr_zero(static_cast<unsigned>(bits)) + 1);
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
}  // namespace

// Two passes: the row split into r, g, b planes first (into the outputs), then the arithmetic on
// the planes in place. GCC does not vectorise the arithmetic reading interleaved RGB (stride 3);
// on contiguous planes it does (SSE2's 16-bit lanes): 0.6 ms of CPU per 780x580 frame instead
// of 1.9 ms in a build without -march=native, where this function was 70% of live_bench's CPU
// time (perf). The same arithmetic, so the same bytes (checked on all 2^24 colours).
void internal::RgbRowToYuv(const uint8_t* __restrict in, int n, uint8_t* __restrict c0,
                           uint8_t* __restrict c1, uint8_t* __restrict c2) {
  SplitRgb(in, n, c0, c1, c2);
  RgbPlanesToYuv(n, c0, c1, c2);
}

void internal::RgbPlanesToYuv(int n, uint8_t* __restrict c0, uint8_t* __restrict c1,
                              uint8_t* __restrict c2) {
  for (int x = 0; x < n; ++x) {
    const uint16_t r = c0[x], g = c1[x], b = c2[x];
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

namespace {

// An RGB row with any pixel and channel strides into R, G and B planes.
void SplitRgbStrided(const uint8_t* in, int n, std::ptrdiff_t pixel, std::ptrdiff_t channel,
                     uint8_t* __restrict c0, uint8_t* __restrict c1, uint8_t* __restrict c2) {
  for (int x = 0; x < n; ++x) {
    const uint8_t* p = in + x * pixel;
    c0[x] = p[0];
    c1[x] = p[channel];
    c2[x] = p[2 * channel];
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

#ifdef PATLAB_SEGMENT_AVX512
// A table of 256 bytes in four registers, looked up 64 indices at a time: two permutes of 128
// entries each (index bit 6 picks the register of a pair), the pair chosen by index bit 7.
struct ByteTable {
  __m512i part[4];
  explicit ByteTable(const std::array<uint8_t, 256>& t) {
    for (int i = 0; i < 4; ++i) part[i] = _mm512_loadu_si512(t.data() + 64 * i);
  }
  __m512i operator()(__m512i index) const {
    const __m512i low = _mm512_permutex2var_epi8(part[0], index, part[1]);
    const __m512i high = _mm512_permutex2var_epi8(part[2], index, part[3]);
    return _mm512_mask_blend_epi8(_mm512_movepi8_mask(index), low, high);
  }
};

// out[x] = first_class[bits0[c0[x]] & bits1[c1[x]] & bits2[c2[x]]] for x < n, 64 pixels at a
// time (the last ones under a mask).
void LabelRow(const uint8_t* c0, const uint8_t* c1, const uint8_t* c2, int n,
              const std::array<std::array<uint8_t, 256>, 3>& channel_bits,
              const std::array<uint8_t, 256>& first_class, uint8_t* out) {
  const ByteTable bits0(channel_bits[0]), bits1(channel_bits[1]), bits2(channel_bits[2]);
  const ByteTable label(first_class);
  for (int x = 0; x < n; x += 64) {
    const __mmask64 lanes = n - x >= 64 ? ~__mmask64{0} : (__mmask64{1} << (n - x)) - 1;
    const __m512i v0 = _mm512_maskz_loadu_epi8(lanes, c0 + x);
    const __m512i v1 = _mm512_maskz_loadu_epi8(lanes, c1 + x);
    const __m512i v2 = _mm512_maskz_loadu_epi8(lanes, c2 + x);
    const __m512i bits = _mm512_and_si512(_mm512_and_si512(bits0(v0), bits1(v1)), bits2(v2));
    _mm512_mask_storeu_epi8(out + x, lanes, label(bits));
  }
}
#endif

}  // namespace

bool internal::HaveAvx512Rows() {
#ifdef PATLAB_SEGMENT_AVX512
  return true;
#else
  return false;
#endif
}

// internal::RgbRowToYuv 32 pixels at a time with byte multiply-adds (vpmaddubsw: unsigned bytes
// times signed byte coefficients, pairs summed into 16 bits, saturating, so each pair's
// coefficients must sum to at most 128). Two byte permutes make each pixel's (r, g) and (g, b)
// pairs; then, in 16-bit lanes and exactly as internal::RgbRowToYuv:
//   77r + 150g + 29b = (77r + 51g) + (99g + 29b), each at most 128 * 255 (no saturation); the sum
//                      plus 128 is at most 65408, so it wraps nowhere in unsigned 16-bit lanes;
//   43r + 85g and 107g + 21b (coefficients summing to 128) are U's and V's S;
//   64b and 64r come from the high byte of (g, b) and the low byte of (r, g).
void internal::RgbRowToYuvAvx512(const uint8_t* __restrict in, int n, uint8_t* __restrict c0,
                                 uint8_t* __restrict c1, uint8_t* __restrict c2) {
#ifndef PATLAB_SEGMENT_AVX512
  RgbRowToYuv(in, n, c0, c1, c2);
#else
  alignas(64) std::array<uint8_t, 64> rg_index, gb_index;
  for (int p = 0; p < 32; ++p) {
    rg_index[2 * p] = static_cast<uint8_t>(3 * p);
    rg_index[2 * p + 1] = static_cast<uint8_t>(3 * p + 1);
    gb_index[2 * p] = static_cast<uint8_t>(3 * p + 1);
    gb_index[2 * p + 1] = static_cast<uint8_t>(3 * p + 2);
  }
  const __m512i rg_at = _mm512_load_si512(rg_index.data());
  const __m512i gb_at = _mm512_load_si512(gb_index.data());
  const auto pairs = [](int8_t a, int8_t b) {  // the coefficients (a, b) in every 16-bit lane
    return _mm512_set1_epi16(static_cast<int16_t>(
        static_cast<uint8_t>(a) | (static_cast<uint16_t>(static_cast<uint8_t>(b)) << 8)));
  };
  const __m512i y_rg = pairs(77, 51), y_gb = pairs(99, 29);
  const __m512i u_rg = pairs(43, 85), v_gb = pairs(107, 21);
  const __m512i c128 = _mm512_set1_epi16(128), one = _mm512_set1_epi16(1);
  const __m512i c16448 = _mm512_set1_epi16(16448), c255 = _mm512_set1_epi16(255);
  for (int x = 0; x < n; x += 32) {
    const int bytes = 3 * std::min(32, n - x);
    const __mmask64 first = bytes >= 64 ? ~__mmask64{0} : (__mmask64{1} << bytes) - 1;
    const __mmask64 second = bytes > 64 ? (__mmask64{1} << (bytes - 64)) - 1 : 0;
    const __m512i lo = _mm512_maskz_loadu_epi8(first, in + 3 * x);
    const __m512i hi =  // no pointer past the row when no byte of it is read
        second != 0 ? _mm512_maskz_loadu_epi8(second, in + 3 * x + 64) : _mm512_setzero_si512();
    const __m512i rg = _mm512_permutex2var_epi8(lo, rg_at, hi);
    const __m512i gb = _mm512_permutex2var_epi8(lo, gb_at, hi);
    const __m512i y = _mm512_srli_epi16(
        _mm512_add_epi16(
            _mm512_add_epi16(_mm512_maddubs_epi16(rg, y_rg), _mm512_maddubs_epi16(gb, y_gb)), c128),
        8);
    const __m512i su = _mm512_srli_epi16(_mm512_add_epi16(_mm512_maddubs_epi16(rg, u_rg), one), 1);
    const __m512i sv = _mm512_srli_epi16(_mm512_add_epi16(_mm512_maddubs_epi16(gb, v_gb), one), 1);
    const __m512i b64 = _mm512_slli_epi16(_mm512_srli_epi16(gb, 8), 6);
    const __m512i r64 = _mm512_slli_epi16(_mm512_and_si512(rg, c255), 6);
    const __m512i u = _mm512_min_epu16(
        _mm512_srli_epi16(_mm512_sub_epi16(_mm512_add_epi16(b64, c16448), su), 7), c255);
    const __m512i v = _mm512_min_epu16(
        _mm512_srli_epi16(_mm512_sub_epi16(_mm512_add_epi16(r64, c16448), sv), 7), c255);
    const __mmask32 lanes = n - x >= 32 ? ~__mmask32{0} : (__mmask32{1} << (n - x)) - 1;
    _mm512_mask_cvtepi16_storeu_epi8(c0 + x, lanes, y);
    _mm512_mask_cvtepi16_storeu_epi8(c1 + x, lanes, u);
    _mm512_mask_cvtepi16_storeu_epi8(c2 + x, lanes, v);
  }
#endif
}

// Row y of the frame into the three planes of the thresholds' colour space: packed rows as they
// are (the AVX-512 conversion reads them directly), other RGB layouts gathered first.
void Segmenter::RowToPlanes(const camera::ImageView& image, int y, uint8_t* c0, uint8_t* c1,
                            uint8_t* c2) const {
  const uint8_t* in = image.Row(y);
  const int w = image.width_px;
  const bool yuv_lut = lut_.space() == ColorSpace::kYuv;
  if (image.format != camera::PixelFormat::kRgb8) {
    (yuv_lut ? SplitUyvy : UyvyRowToRgb)(in, w / 2, c0, c1, c2);
  } else if (image.PackedPixels()) {
    (yuv_lut ? internal::RgbRowToYuvAvx512 : SplitRgb)(in, w, c0, c1, c2);
  } else {
    SplitRgbStrided(in, w, image.pixel_stride, image.channel_stride, c0, c1, c2);
    if (yuv_lut) internal::RgbPlanesToYuv(w, c0, c1, c2);
  }
}

void Segmenter::Classify(const camera::ImageView& image) {
  PATLAB_CHECK(image.width_px > 0 && image.height_px > 0);
  PATLAB_CHECK(image.format == camera::PixelFormat::kRgb8 || image.PackedPixels());
  width_ = image.width_px;
  height_ = image.height_px;
  const int w = width_;
  class_image_.resize(static_cast<size_t>(w) * height_);
  planes_.resize(3 * static_cast<size_t>(w));
  uint8_t* c0 = planes_.data();
  uint8_t* c1 = c0 + w;
  uint8_t* c2 = c1 + w;
  const bool rgb = image.format == camera::PixelFormat::kRgb8;
  if (!rgb && w % 2 != 0) {
    // UYVY frames have even widths (frame_io checks); a last lone pixel would have no U, V.
    c0[w - 1] = c1[w - 1] = c2[w - 1] = 0;
  }
  const int num_boxes = static_cast<int>(boxes_.size());
  for (int y = 0; y < height_; ++y) {
    uint8_t* out = class_image_.data() + static_cast<size_t>(y) * w;
    RowToPlanes(image, y, c0, c1, c2);
#ifdef PATLAB_SEGMENT_AVX512
    if (use_tables_) {
      LabelRow(c0, c1, c2, w, channel_bits_, first_class_, out);
      if (!rgb && w % 2 != 0) out[w - 1] = 0;
      continue;
    }
#endif
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

// The first x' >= x with row[x'] != c, or w: 32 pixels at a time while they are all c (a run of
// no class, most of a frame, and a long run of one class), then eight, the first differing byte
// of a word found from its lowest differing bit (its highest on a big-endian machine).
inline int SkipRun(const uint8_t* row, int x, int w, uint8_t c) {
  static_assert(std::endian::native == std::endian::little ||
                std::endian::native == std::endian::big);
  const uint64_t same = 0x0101010101010101ULL * c;
  for (; x + 32 <= w; x += 32) {  // 32 pixels a compare while all are c
    std::array<uint64_t, 4> words;
    std::memcpy(words.data(), row + x, 32);
    if (((words[0] ^ same) | (words[1] ^ same) | (words[2] ^ same) | (words[3] ^ same)) != 0) {
      break;
    }
  }
  for (; x + 8 <= w; x += 8) {
    uint64_t word;
    std::memcpy(&word, row + x, 8);
    const uint64_t differ = word ^ same;
    if (differ == 0) continue;
    const int bit = std::endian::native == std::endian::little ? std::countr_zero(differ)
                                                               : std::countl_zero(differ);
    return x + bit / 8;
  }
  while (x < w && row[x] == c) ++x;
  return x;
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
    for (int x = SkipRun(row, 0, w, 0); x < w; x = SkipRun(row, x, w, 0)) {
      const uint8_t c = row[x];
      const int start = x;
      x = SkipRun(row, x + 1, w, c);
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

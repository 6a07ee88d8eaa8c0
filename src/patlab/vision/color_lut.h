// Stage 2 of the vision pipeline: colour classes and their lookup table (CMVision, Bruce et al.
// IROS 2000). Each class is a box in YUV (or RGB): lo..hi per channel, inclusive. The lookup
// table keeps one 32-bit mask per channel value, bit k set when value lies in class k's range;
// a pixel's classes are the AND of its three masks, and the lowest set bit (the class listed
// first) wins where boxes overlap. One pass builds all classes at once, unlike one binary
// threshold per colour.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"

namespace patlab::vision {

inline constexpr int kMaxColorClasses = 32;  // one bit each in a 32-bit mask

enum class ColorSpace { kYuv, kRgb };
inline constexpr EnumNames<ColorSpace, 2> kColorSpaceNames{
    {{{ColorSpace::kYuv, "yuv"}, {ColorSpace::kRgb, "rgb"}}}};

struct ChannelRange {
  int lo = 0;  // 0..255, inclusive
  int hi = 255;
};

struct ColorClass {
  std::string name;
  std::array<uint8_t, 3> display_rgb = {255, 255, 255};  // colour used in debug images
  double merge = 0.0;    // CMVision's region merge density (read and kept; not used here)
  int expected_num = 0;  // CMVision's expected regions per frame (read and kept; not used here)
  std::array<ChannelRange, 3> range;  // Y U V (or R G B), in the order of ColorSpace
  // Regions of this class smaller than this are dropped; 0 = use the pipeline's default.
  int min_area_px = 0;
  // Regions of this class larger than this are dropped (a colour that also covers shadows or a
  // robot's body, e.g. a black front sector); 0 = no limit.
  int max_area_px = 0;
};

struct Thresholds {
  ColorSpace space = ColorSpace::kYuv;
  std::vector<ColorClass> classes;  // 1 .. kMaxColorClasses
  std::string source;               // file it came from, for messages

  // Index of the class named `name`, or -1.
  int Find(std::string_view name) const;
};

// The per-channel mask tables built from thresholds.
class ColorLut {
 public:
  explicit ColorLut(const Thresholds& thresholds);

  ColorSpace space() const { return space_; }
  int num_classes() const { return num_classes_; }
  // Bit k set when (a, b, c) lies in class k's box (a, b, c in the thresholds' space).
  uint32_t Mask(int a, int b, int c) const { return tables_[0][a] & tables_[1][b] & tables_[2][c]; }
  // The winning class (lowest set bit) or -1.
  int Classify(int a, int b, int c) const {
    const uint32_t m = Mask(a, b, c);
    return m == 0 ? -1 : __builtin_ctz(m);
  }
  const std::array<uint32_t, 256>& table(int channel) const { return tables_[channel]; }

 private:
  ColorSpace space_;
  int num_classes_;
  std::array<std::array<uint32_t, 256>, 3> tables_{};
};

}  // namespace patlab::vision

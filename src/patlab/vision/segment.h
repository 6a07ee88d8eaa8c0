// Stages 2-4 of the vision pipeline (CMVision, Bruce et al. IROS 2000):
//   2. classify  - every pixel into its colour class (the class image): the first class whose
//                  box holds it, as ColorLut's lookup gives it, a row at a time with no
//                  per-pixel branch: byte compares per class (vectorised), or, with AVX-512 VBMI
//                  and at most 8 classes, ColorLut's per-channel masks looked up 64 pixels at a
//                  time from registers;
//   3. encode    - run-length encode each row (32 pixels a compare where they are all one
//                  class), then union-find joins runs of the same class that overlap on
//                  adjacent rows (4-connectivity);
//   4. regions   - one pass over the runs accumulates area, bounding box and the sub-pixel
//                  centroid of every connected region; filters drop small or sparse regions;
//                  regions are grouped by class and sorted by area, largest first.
// All buffers live in the Segmenter and are reused, so after the first frame of a size nothing
// is allocated per frame, and never per pixel.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/vision/color_lut.h"

namespace patlab::vision {

// A horizontal run of pixels of one class: columns x_begin .. x_end inclusive on row y.
struct Run {
  int32_t x_begin;
  int32_t x_end;
  int32_t y;
  int32_t parent;  // union-find link: index of an earlier run of the same region (or itself)
  int32_t colour;  // class index
};

struct Region {
  int colour = 0;                                  // class index into Thresholds::classes
  int area_px = 0;                                 // number of pixels
  int x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // bounding box, inclusive
  // Mean pixel position; pixel (i, j) has its centre at (i, j) (see image.h).
  Vec2 centroid_px = Vec2::Zero();

  // Fraction of the bounding box covered: pi/4 = 0.785 for a disc, 1 for an axis-aligned box.
  double Fill() const {
    return static_cast<double>(area_px) /
           (static_cast<double>(x_max - x_min + 1) * static_cast<double>(y_max - y_min + 1));
  }
};

struct SegmenterOptions {
  // Regions with fewer pixels are dropped (noise); a class's own min_area_px overrides it.
  // Larger values drop more noise but also small, distant patches. >= 1.
  int min_area_px = 4;
  // Regions covering less than this fraction of their bounding box are dropped (thin lines,
  // ragged noise). 0 keeps everything; a disc has 0.785. In [0, 1].
  double min_fill = 0.0;
};

// Every broken constraint (core/options.h); Validate throws InputError with the first.
std::vector<OptionsProblem> Check(const SegmenterOptions& options);
void Validate(const SegmenterOptions& options);

class Segmenter {
 public:
  Segmenter(const Thresholds& thresholds, const SegmenterOptions& options);

  // Stage 2. Fills class_image(): 0 = no class, k + 1 = class k, exactly lut().Classify of the
  // pixel + 1. Frames in either pixel format work with thresholds in either colour space (the
  // pixel is converted with image.h's BT.601 RgbToYuv / YuvToRgb when the spaces differ). The
  // frame is read in place, a row at a time, whatever its strides (an Image is a packed view);
  // the same classes for any layout of the same pixels.
  void Classify(const camera::ImageView& image);
  // Stage 3. Run-length encodes class_image() and joins runs into regions (union-find).
  void EncodeRuns();
  // Stage 4. Region statistics and filters.
  void ExtractRegions();

  // Stages 2-4 in order.
  void Process(const camera::ImageView& image) {
    Classify(image);
    EncodeRuns();
    ExtractRegions();
  }

  int width_px() const { return width_; }
  int height_px() const { return height_; }
  const std::vector<uint8_t>& class_image() const { return class_image_; }
  const std::vector<Run>& runs() const { return runs_; }
  // Kept regions, grouped by class in class order, each group sorted by area (largest first,
  // ties by centroid y then x).
  const std::vector<Region>& regions() const { return regions_; }
  std::span<const Region> RegionsOf(int colour) const;
  // Connected regions before the area and fill filters.
  int num_raw_regions() const { return num_raw_regions_; }
  const ColorLut& lut() const { return lut_; }

 private:
  void RowToPlanes(const camera::ImageView& image, int y, uint8_t* c0, uint8_t* c1,
                   uint8_t* c2) const;

  ColorLut lut_;
  SegmenterOptions options_;
  std::vector<int> min_area_px_;  // per class
  std::vector<int> max_area_px_;  // per class; INT_MAX = no limit
  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> class_image_;
  // Stage 2 works one row at a time: the row's pixels are converted (vectorised) into three
  // planes of the thresholds' channels, then every class's box test runs over the planes as
  // byte compares, last class first, so the first class listed wins (as ColorLut's lowest bit).
  // Exact for every colour and free of per-pixel branches.
  struct ClassBox {
    std::array<uint8_t, 3> lo;     // lower bound per channel
    std::array<uint8_t, 3> width;  // hi - lo per channel: v is inside when uint8(v - lo) <= width
  };
  std::vector<ClassBox> boxes_;
  // With at most 8 classes and AVX-512 VBMI (a byte permute of 64 table entries), the box tests
  // are table lookups instead (CMVision's own scheme): channel_bits_[ch][v] has bit k set when
  // class k's range on channel ch holds v, so a pixel's classes are the AND of its three
  // channels' entries, and first_class_[bits] is the label of the lowest bit (0 for none). The
  // same labels as the box tests (ColorLut's own masks), at a cost that does not grow with the
  // classes.
  bool use_tables_ = false;
  std::array<std::array<uint8_t, 256>, 3> channel_bits_{};
  std::array<uint8_t, 256> first_class_{};
  std::vector<uint8_t> planes_;  // 3 x width_: the current row's channels
  std::vector<Run> runs_;
  struct Accumulator {
    int64_t area, sum_x, sum_y;
    int x_min, y_min, x_max, y_max, colour;
  };
  std::vector<int32_t> label_;
  std::vector<Accumulator> accumulators_;
  std::vector<Region> regions_;
  std::vector<int> class_begin_;  // regions_ index where each class starts; size classes + 1
  int num_raw_regions_ = 0;
};

}  // namespace patlab::vision

// Stages 2-4 of the vision pipeline (CMVision, Bruce et al. IROS 2000):
//   2. classify  - every pixel through the colour lookup table into a class image;
//   3. encode    - run-length encode each row, then union-find joins runs of the same class
//                  that overlap on adjacent rows (4-connectivity);
//   4. regions   - one pass over the runs accumulates area, bounding box and the sub-pixel
//                  centroid of every connected region; filters drop small or sparse regions;
//                  regions are grouped by class and sorted by area, largest first.
// All buffers live in the Segmenter and are reused, so after the first frame of a size nothing
// is allocated per frame, and never per pixel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/image.h"

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

  // Stage 2. Fills class_image(): 0 = no class, k + 1 = class k. Frames in either pixel format
  // work with thresholds in either colour space (the pixel is converted with BT.601 when the
  // spaces differ).
  void Classify(const Image& image);
  // Stage 3. Run-length encodes class_image() and joins runs into regions (union-find).
  void EncodeRuns();
  // Stage 4. Region statistics and filters.
  void ExtractRegions();

  // Stages 2-4 in order.
  void Process(const Image& image) {
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
  ColorLut lut_;
  SegmenterOptions options_;
  std::vector<int> min_area_px_;  // per class
  std::vector<int> max_area_px_;  // per class; INT_MAX = no limit
  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> class_image_;
  // RGB frames with YUV thresholds: a 64^3 table over RGB cells of 4x4x4 values holding the
  // class + 1 (0: none) where every colour of the cell has the same class, or kMixedCell
  // where it may not; mixed pixels are then classified exactly through BT.601. Built on the
  // first such frame. Exact, and one lookup for almost every pixel.
  static constexpr uint8_t kMixedCell = 0xff;
  void BuildRgbCells();
  std::vector<uint8_t> rgb_cells_;
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

// Thresholds from labelled samples, behind `patlab thresholds` (docs/thresholds.md): an image and
// a labels file naming, per colour class, sample pixels (points, rectangles, or the pixels of one
// colour in a label mask image) -> one box per class in the space the lookup table uses
// (color_lut.h; YUV as CMVision), with robust bounds and a margin, and a report of what the boxes
// do on the sample: how many of each class's own pixels its box catches, how many pixels labelled
// otherwise or not labelled it catches too, and which boxes overlap.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/options.h"
#include "patlab/vision/color_lut.h"

namespace patlab::vision {

struct ThresholdsFitOptions {
  // Each bound is a percentile of the class's sample values per channel (nearest rank on the
  // sorted values: lo = v[floor(p_lo/100 (n-1))], hi = v[ceil(p_hi/100 (n-1))]), so a few mixed
  // pixels at a patch's edge do not widen the box. 0 and 100: the sample's minimum and maximum.
  // In [0, 50) and (50, 100].
  double lower_percentile = 1.0;
  double upper_percentile = 99.0;
  // Levels (0..255 scale) added below lo and above hi, clamped to 0..255: room for pixels the
  // sample did not see (lighting elsewhere on the field, sensor noise). Larger: fewer misses,
  // more overlap with neighbouring colours. In [0, 128].
  int margin_levels = 6;
  ColorSpace space = ColorSpace::kYuv;  // the thresholds' space (CMVision's is YUV)
};

std::vector<OptionsProblem> Check(const ThresholdsFitOptions& options);
void Validate(const ThresholdsFitOptions& options);

// One colour class of a labels file. Coordinates are pixels (column x, row y), inclusive.
struct LabelClass {
  std::string name;
  int line = 0;  // where its table starts, for messages
  bool has_display = false;
  std::array<uint8_t, 3> display_rgb = {255, 255, 255};
  std::vector<std::array<int, 2>> points;      // [x, y]: the disc of Labels::point_radius_px
  std::vector<int> point_lines;                // line of each point
  std::vector<std::array<int, 4>> rectangles;  // [x0, y0, x1, y1], x0 <= x1, y0 <= y1
  std::vector<int> rectangle_lines;
  bool has_mask_rgb = false;
  std::array<uint8_t, 3> mask_rgb = {0, 0, 0};  // this class's colour in the mask image
  int min_area_px = 0;                          // passed to the thresholds file as they are
  int max_area_px = 0;
};

// A labels file (docs/file-formats.md, "Labels files"; read by formats/labels_file.h):
//   image = "frame.png"          # required, relative to the labels file's folder
//   mask = "frame.mask.png"      # optional label mask, same size as the image
//   point_radius_px = 1          # optional (default 0): a point samples the disc of this radius
//   [[class]]
//   name = "blue"
//   display = [0, 0, 255]        # optional debug colour (default: the mean colour of the sample)
//   points = [[120, 44], [130, 47]]
//   rects = [[200, 10, 205, 14]] # [x0, y0, x1, y1], inclusive
//   mask = [0, 0, 255]           # optional: pixels of this colour in the mask image
//   min_area_px = 10             # optional, copied into the thresholds file
//   max_area_px = 300            # optional, copied into the thresholds file
struct Labels {
  std::string source;  // the labels file, for messages
  std::string image_path;
  std::string mask_path;  // empty: no mask
  int image_line = 0, mask_line = 0;
  int point_radius_px = 0;
  std::vector<LabelClass> classes;
};

// Every class must be one of `known` (e.g. the detector palette): InputError at the class's line
// naming the first that is not.
void CheckClassesKnown(const Labels& labels, const std::vector<std::string>& known);

// The label of every pixel (row-major): -1 unlabelled, else the class index. Where two classes
// label the same pixel, the one listed first keeps it. InputError (file:line) for a point or
// rectangle outside the image, a mask of another size, a class that labels no pixel (a mask
// colour absent from the mask).
std::vector<int> LabelPixels(const Labels& labels, int width_px, int height_px,
                             const camera::Image* mask);

struct ClassFit {
  std::string name;
  long samples = 0;            // pixels labelled with this class
  long caught_own = 0;         // ... that the lookup table classifies as this class
  long caught_other = 0;       // pixels labelled with another class classified as this class
  long caught_unlabelled = 0;  // unlabelled pixels classified as this class
  std::array<ChannelRange, 3> range;
};

struct ClassOverlap {
  int a = 0, b = 0;     // class indices, a < b
  double volume = 0.0;  // of the intersection of the two boxes, in levels^3 (inclusive counts)
  long a_in_b = 0;      // samples of a inside b's box
  long b_in_a = 0;      // samples of b inside a's box
};

struct ThresholdsFit {
  Thresholds thresholds;
  std::vector<ClassFit> classes;
  std::vector<ClassOverlap> overlaps;  // pairs whose boxes intersect, in (a, b) order
  long labelled_px = 0, unlabelled_px = 0;
};

// The fit on `image` (any PixelFormat; converted to the options' space as ColorLut sees it) with
// `labels` from LabelPixels. Class order, names and areas follow the labels file.
ThresholdsFit FitThresholds(const camera::Image& image, const std::vector<int>& pixel_labels,
                            const Labels& labels, const ThresholdsFitOptions& options);

// The thresholds in our TOML form (ParseThresholdsToml reads it back identically), with
// `comment` (lines without '#') at the top.
std::string ThresholdsToml(const Thresholds& thresholds, const std::string& comment);

// The report for people: per class its box, samples and catches; the overlapping pairs.
std::string ThresholdsFitReport(const ThresholdsFit& fit);

}  // namespace patlab::vision

// Pattern sheets -> pattern files and codebooks (behind `patlab import`), through patlab's own
// segmentation (segment.h): no hand measurement.
//
// A sheet is an SSL-Vision pattern sheet: a grid of 200 x 200 px cells at 1 px = 1 mm, one robot
// top per cell, its ID the cell index in row-major order; a blue centre (key) patch, coloured
// dots (pink, green, cyan or white), the robot's front up (so image up is the model's +x and
// image left its +y), and optionally a yellow bar beside the cell whose length in px is the
// robot's height in mm. Stages:
//   1. segment   - the sheet through a Segmenter with fixed RGB classes for the sheet colours;
//   2. cells     - per cell: the key (the largest blue region in it) and the dots (regions of
//                  a dot colour of dot size within reach of the key), positions in mm relative
//                  to the key; cells without a key are empty and skipped. A cell whose
//                  coloured regions near the key are larger than dots holds ring sectors (the
//                  KIKS design), where same-coloured neighbours merge into one region: its
//                  ring is read by angle instead, split at the sheet's sector boundaries (every
//                  colour change seen in any ring cell), and each coloured sector becomes one
//                  dot: the sector's centroid with the radius of the largest disc about it
//                  inside the sector;
//   3. slots     - the dot positions of every cell clustered (within slot_tolerance_mm) into
//                  slots, averaged: the union layout;
//   4. layouts   - cells grouped by which slots hold a dot (an absent dot is part of the code:
//                  cells with different dot sets are different layouts); one pattern per
//                  layout, its ID slots ordered front to back, then left to right;
//   5. codebooks - per layout the colourings of its cells, id = cell index, checked against the
//                  layout's symmetry (detect/codebook.h): colourings the rule makes confusable
//                  are left out of the codebook and listed in ImportedLayout::dropped.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"

namespace patlab::design {

struct SheetImportOptions {
  int cell_px = 200;       // cell size in px (SSL-Vision sheets: 200); > 0
  double mm_per_px = 1.0;  // scale (SSL-Vision sheets: 1 px = 1 mm); > 0
  // Dots of two cells closer than this (mm) are one slot. Larger merges slots that differ;
  // smaller splits one slot drawn with rounding differences. > 0.
  double slot_tolerance_mm = 8.0;
  // Symmetry tolerance (mm) for each layout's codebook check (patlab ids --tolerance). >= 0.
  double symmetry_tolerance_mm = 10.0;
  // The name of the patterns: <name> for a single layout, <name>-<k> (k = 1, 2, ...) for more.
  std::string name;
};
// Fields named as the flags of `patlab import`: --cell-px in [20, 10000], --mm-per-px > 0,
// --slot-tolerance > 0, --tolerance >= 0.
std::vector<OptionsProblem> Check(const SheetImportOptions& options);
void Validate(const SheetImportOptions& options);

// One dot of one cell.
struct SheetDot {
  Vec2 position_mm = Vec2::Zero();  // relative to the key centre, model frame
  double radius_mm = 0.0;           // from the region's area
  std::string colour;
  int slot = -1;  // index into SheetImport::slots
};

struct SheetCell {
  int index = 0;  // row-major cell index = the robot ID
  double key_radius_mm = 0.0;
  std::vector<SheetDot> dots;
  int height_mm = 0;  // the yellow bar's length; 0 without a bar
  int layout = -1;    // index into SheetImport::layouts
};

struct ImportedLayout {
  Pattern pattern;
  detect::Codebook codebook;                         // the cells' IDs that the symmetry rule keeps
  std::vector<std::pair<int, std::string>> dropped;  // (cell ID, why) left out of the codebook
  std::vector<int> cells;                            // the cell indices of this layout
};

struct SheetImport {
  std::string file;
  int columns = 0, rows = 0;
  std::vector<SheetCell> cells;  // the cells with a key, in index order
  std::vector<Vec2> slots;       // union layout: slot positions (mm), front to back
  // Ring-sector sheets only (see below): the sector boundaries in model degrees (0 = front,
  // 90 = left), ascending; empty for dot sheets.
  std::vector<double> sector_bounds_deg;
  std::vector<ImportedLayout> layouts;
};

// Stages 1-5 on a decoded sheet. Throws InputError naming `file` when the image is not a grid
// of cells or no cell holds a recognisable pattern (a key and at least one dot).
SheetImport ImportSheet(const camera::Image& image, const std::string& file,
                        const SheetImportOptions& options);

// The pattern file and codebook file texts of one layout (formats: patterns/README.md).
std::string PatternFileText(const ImportedLayout& layout, const SheetImport& sheet);
std::string CodebookFileText(const ImportedLayout& layout, const SheetImport& sheet);

}  // namespace patlab::design

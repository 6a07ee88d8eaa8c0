// Internals of sheet_import.cpp shared with sheet_sectors.cpp (not a public interface).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "patlab/design/sheet_import.h"
#include "patlab/vision/segment.h"

namespace patlab::design::internal {

// Segmenter classes of a sheet: 0 the key, 1-4 the dot colours, 5 the height bar.
constexpr int kBlue = 0, kYellow = 5;
constexpr std::array<const char*, 6> kClassNames = {"blue", "pink",  "green",
                                                    "cyan", "white", "yellow"};
constexpr double kDotAreaMinMm2 = 200.0;   // a dot is Ø16 mm or more ...
constexpr double kDotAreaMaxMm2 = 3000.0;  // ... and at most Ø62 mm (a robot top is far larger)
constexpr double kReachMm = 120.0;         // dots lie within this distance of the key

// A cell whose dot-coloured regions around the key are too large to be dots: ring sectors
// (the KIKS design). Adjacent sectors of one colour are one region, so the sectors are found
// by angle instead: colour[b] is the dot class (1-4) that most pixels within kReachMm of the key
// have at model angle b..b+1 degrees (0 = front, 90 = left), -1 where fewer than 3 have one.
struct CellRing {
  int cell = 0;  // index into SheetImport::cells
  Vec2 key_px = Vec2::Zero();
  std::array<int, 360> colour{};
};

// Whether the cell of the key holds ring sectors: a dot-coloured region larger than a dot whose
// centroid is within kReachMm of the key.
bool HasRingSectors(const vision::Segmenter& seg, const vision::Region& key,
                    const SheetImportOptions& o);
CellRing ReadRing(const vision::Segmenter& seg, const vision::Region& key,
                  const SheetImportOptions& o);

// Splits every ring cell into sectors at the sheet's sector boundaries (the colour changes seen
// in any ring cell, clustered within 5 degrees) and gives each ring cell one dot per sector it
// colours: the sector's centroid, with the radius of the largest disc about it inside the
// sector. Sets sheet->sector_bounds_deg. Throws InputError naming the file when no ring cell
// shows a boundary (one colour all round in every cell).
void SplitRings(const vision::Segmenter& seg, const std::vector<CellRing>& rings,
                const SheetImportOptions& o, SheetImport* sheet);

}  // namespace patlab::design::internal

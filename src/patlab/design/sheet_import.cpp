#include "patlab/design/sheet_import.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/sheet_import_internal.h"
#include "patlab/io/name.h"
#include "patlab/vision/segment.h"

namespace patlab::design {

namespace {

using internal::kBlue;
using internal::kClassNames;
using internal::kDotAreaMaxMm2;
using internal::kDotAreaMinMm2;
using internal::kReachMm;
using internal::kYellow;

// The sheet colours are pure RGB primaries and mixes drawn with anti-aliased edges; each class
// takes the colour and its edge pixels that are still clearly that colour. The cell background
// (0, 96..128, 0) and the black robot top fall in none.
vision::Thresholds SheetThresholds() {
  vision::Thresholds t;
  t.space = vision::ColorSpace::kRgb;
  auto add = [&t](const char* name, vision::ChannelRange r, vision::ChannelRange g,
                  vision::ChannelRange b) {
    vision::ColorClass c;
    c.name = name;
    c.range = {r, g, b};
    t.classes.push_back(c);
  };
  add(kClassNames[0], {0, 90}, {0, 90}, {160, 255});
  add(kClassNames[1], {160, 255}, {0, 90}, {80, 255});
  add(kClassNames[2], {0, 90}, {190, 255}, {0, 90});
  add(kClassNames[3], {0, 90}, {190, 255}, {160, 255});
  add(kClassNames[4], {190, 255}, {190, 255}, {190, 255});
  add(kClassNames[5], {190, 255}, {190, 255}, {0, 90});
  return t;
}

struct CellKey {
  int column = 0, row = 0;
};

CellKey CellOf(const Vec2& centroid_px, int cell_px) {
  return {static_cast<int>(std::floor(centroid_px.x() / cell_px)),
          static_cast<int>(std::floor(centroid_px.y() / cell_px))};
}

// Stage 2 for one cell: the key is the largest blue region whose centroid lies in the cell.
// Returns the key, nullptr for a cell without one.
const vision::Region* ReadCell(const vision::Segmenter& seg, const SheetImport& sheet,
                               const SheetImportOptions& o, int index, SheetCell* cell) {
  const int column = index % sheet.columns, row = index / sheet.columns;
  const vision::Region* key = nullptr;
  for (const vision::Region& r : seg.RegionsOf(kBlue)) {
    const CellKey k = CellOf(r.centroid_px, o.cell_px);
    if (k.column == column && k.row == row && (key == nullptr || r.area_px > key->area_px)) {
      key = &r;
    }
  }
  if (key == nullptr) return nullptr;
  const double mm2_per_px = o.mm_per_px * o.mm_per_px;
  cell->index = index;
  cell->key_radius_mm = std::sqrt(key->area_px * mm2_per_px / std::numbers::pi);
  for (int c = 1; c < kYellow; ++c) {
    for (const vision::Region& r : seg.RegionsOf(c)) {
      const double area_mm2 = r.area_px * mm2_per_px;
      if (area_mm2 < kDotAreaMinMm2 || area_mm2 > kDotAreaMaxMm2) continue;
      const Vec2 d = (r.centroid_px - key->centroid_px) * o.mm_per_px;
      if (d.norm() > kReachMm) continue;
      // Image right is -y, image down is -x (front up).
      cell->dots.push_back(
          {Vec2(-d.y(), -d.x()), std::sqrt(area_mm2 / std::numbers::pi), kClassNames[c], -1});
    }
  }
  for (const vision::Region& r : seg.RegionsOf(kYellow)) {
    const CellKey k = CellOf(r.centroid_px, o.cell_px);
    if (k.column == column && k.row == row) {
      cell->height_mm = static_cast<int>(std::lround((r.y_max - r.y_min + 1) * o.mm_per_px));
    }
  }
  return key;
}

// Stage 3: greedy clustering in cell order, each slot at the running mean of its dots; slots are
// then ordered front to back (x descending in 1 mm steps), then left to right (y descending).
void ClusterSlots(const SheetImportOptions& o, SheetImport* sheet) {
  std::vector<Vec2> sum;
  std::vector<int> count;
  for (SheetCell& cell : sheet->cells) {
    for (SheetDot& dot : cell.dots) {
      int best = -1;
      for (size_t s = 0; s < sum.size(); ++s) {
        if ((sum[s] / count[s] - dot.position_mm).norm() <= o.slot_tolerance_mm) {
          best = static_cast<int>(s);
          break;
        }
      }
      if (best < 0) {
        best = static_cast<int>(sum.size());
        sum.push_back(Vec2::Zero());
        count.push_back(0);
      }
      sum[best] += dot.position_mm;
      ++count[best];
      dot.slot = best;
    }
  }
  std::vector<int> order(sum.size());
  for (size_t s = 0; s < order.size(); ++s) order[s] = static_cast<int>(s);
  std::vector<Vec2> mean(sum.size());
  for (size_t s = 0; s < sum.size(); ++s) mean[s] = sum[s] / count[s];
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double xa = std::round(mean[a].x()), xb = std::round(mean[b].x());
    return xa != xb ? xa > xb : mean[a].y() > mean[b].y();
  });
  std::vector<int> rank(order.size());
  for (size_t k = 0; k < order.size(); ++k) {
    rank[order[k]] = static_cast<int>(k);
    sheet->slots.push_back(mean[order[k]]);
  }
  for (SheetCell& cell : sheet->cells) {
    for (SheetDot& dot : cell.dots) dot.slot = rank[dot.slot];
    std::sort(cell.dots.begin(), cell.dots.end(),
              [](const SheetDot& a, const SheetDot& b) { return a.slot < b.slot; });
  }
}

// The pattern of one set of occupied slots: key at the origin with the mean key radius, one ID
// patch per slot with the mean radius of its dots.
Pattern LayoutPattern(const SheetImport& sheet, const std::vector<int>& slots,
                      const std::vector<int>& cells, const std::string& name) {
  Pattern p;
  p.name = name;
  double key_radius = 0.0;
  std::vector<double> radius(slots.size(), 0.0);
  for (int c : cells) {
    const SheetCell& cell = sheet.cells[c];
    key_radius += cell.key_radius_mm / cells.size();
    for (size_t k = 0; k < slots.size(); ++k) radius[k] += cell.dots[k].radius_mm / cells.size();
  }
  p.patches.push_back({Vec2::Zero(), key_radius, PatchRole::kKey, ""});
  for (size_t k = 0; k < slots.size(); ++k) {
    p.patches.push_back({sheet.slots[slots[k]], radius[k], PatchRole::kId, ""});
  }
  // Discs drawn touching measure slightly larger than drawn (their anti-aliased edges): shrink
  // each overlapping pair to touch 0.5 mm apart, in proportion, so the pattern file is valid.
  for (size_t i = 0; i < p.patches.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      Patch& a = p.patches[i];
      Patch& b = p.patches[j];
      const double room = (a.position_mm - b.position_mm).norm() - 0.5;
      const double sum = a.radius_mm + b.radius_mm;
      if (sum <= room) continue;
      a.radius_mm *= room / sum;
      b.radius_mm *= room / sum;
    }
  }
  p.key_index = 0;
  p.orientation_pairs = DefaultOrientationPairs(p.patches, 0);
  return p;
}

// Stage 5: the colourings of the layout's cells, kept while unconfusable with those kept before.
void BuildCodebook(const SheetImport& sheet, double tolerance_mm, ImportedLayout* layout) {
  const detect::Symmetry symmetry = detect::FindSymmetry(layout->pattern, tolerance_mm);
  detect::Codebook& book = layout->codebook;
  book.pattern = layout->pattern.name;
  book.num_slots = layout->pattern.size() - 1;
  for (const char* c : {"pink", "green", "cyan", "white"}) {
    for (int cell : layout->cells) {
      for (const SheetDot& d : sheet.cells[cell].dots) {
        if (d.colour == c &&
            std::find(book.colours.begin(), book.colours.end(), c) == book.colours.end()) {
          book.colours.emplace_back(c);
        }
      }
    }
  }
  for (int cell : layout->cells) {
    detect::CodebookEntry entry{sheet.cells[cell].index, {}};
    for (const SheetDot& d : sheet.cells[cell].dots) {
      entry.colour.push_back(static_cast<int>(
          std::find(book.colours.begin(), book.colours.end(), d.colour) - book.colours.begin()));
    }
    // The rule of detect/codebook.h, one entry at a time in ID order, so a confusable colouring
    // is named with the ID it collides with.
    const int stabiliser = detect::StabilisingShift(layout->pattern, symmetry, entry.colour);
    std::string why;
    if (stabiliser != 0) {
      why = "a rotation by shift " + std::to_string(stabiliser) + " maps it onto itself";
    }
    for (const detect::CodebookEntry& other : book.entries) {
      if (!why.empty()) break;
      if (other.colour == entry.colour) {
        why = "the same colours as ID " + std::to_string(other.id);
      } else if (detect::Confusable(layout->pattern, symmetry, other.colour, entry.colour)) {
        why = "a rotation the geometry cannot reject maps ID " + std::to_string(other.id) +
              " onto it";
      }
    }
    if (why.empty()) {
      book.entries.push_back(entry);
    } else {
      layout->dropped.push_back({entry.id, why});
    }
  }
}

}  // namespace

std::vector<OptionsProblem> Check(const SheetImportOptions& o) {
  OptionsChecker check;
  check.IntegerInRange("--cell-px", o.cell_px, 20, 10000);
  check.Positive("--mm-per-px", o.mm_per_px);
  check.Positive("--slot-tolerance", o.slot_tolerance_mm, "mm");
  check.NonNegative("--tolerance", o.symmetry_tolerance_mm, "mm");
  return check.Take();
}

void Validate(const SheetImportOptions& o) { ThrowFirstProblem(Check(o)); }

SheetImport ImportSheet(const camera::Image& image, const std::string& file,
                        const SheetImportOptions& o) {
  Validate(o);
  SheetImport sheet;
  sheet.file = file;
  if (image.width_px % o.cell_px != 0 || image.height_px % o.cell_px != 0) {
    throw InputError(file + ": the sheet is " + std::to_string(image.width_px) + "x" +
                     std::to_string(image.height_px) + " px; expected a grid of " +
                     std::to_string(o.cell_px) + " px cells");
  }
  sheet.columns = image.width_px / o.cell_px;
  sheet.rows = image.height_px / o.cell_px;
  vision::SegmenterOptions so;
  so.min_area_px = 20;
  vision::Segmenter seg(SheetThresholds(), so);
  seg.Process(image);
  std::vector<internal::CellRing> rings;
  for (int index = 0; index < sheet.columns * sheet.rows; ++index) {
    SheetCell cell;
    const vision::Region* key = ReadCell(seg, sheet, o, index, &cell);
    if (key == nullptr) continue;
    if (internal::HasRingSectors(seg, *key, o)) {
      rings.push_back(internal::ReadRing(seg, *key, o));
      rings.back().cell = static_cast<int>(sheet.cells.size());
    } else if (cell.dots.empty()) {
      continue;
    }
    sheet.cells.push_back(std::move(cell));
  }
  if (!rings.empty()) {
    internal::SplitRings(seg, rings, o, &sheet);
    std::erase_if(sheet.cells, [](const SheetCell& c) { return c.dots.empty(); });
  }
  if (sheet.cells.empty()) {
    throw InputError(file + ": no recognisable cells; expected " + std::to_string(o.cell_px) +
                     " px cells each with a blue key patch and coloured dots");
  }
  ClusterSlots(o, &sheet);
  std::map<std::vector<int>, int> layout_of;  // occupied slots -> layout index
  for (size_t c = 0; c < sheet.cells.size(); ++c) {
    std::vector<int> slots;
    for (const SheetDot& d : sheet.cells[c].dots) slots.push_back(d.slot);
    auto [it, inserted] = layout_of.insert({slots, static_cast<int>(sheet.layouts.size())});
    if (inserted) sheet.layouts.emplace_back();
    sheet.cells[c].layout = it->second;
    sheet.layouts[it->second].cells.push_back(static_cast<int>(c));
  }
  const std::string base = o.name.empty() ? std::filesystem::path(file).stem().string() : o.name;
  io::CheckName(base, o.name.empty() ? "the sheet's file stem" : "--name");
  for (auto& [slots, index] : layout_of) {
    ImportedLayout& layout = sheet.layouts[index];
    const std::string name =
        sheet.layouts.size() == 1 ? base : base + "-" + std::to_string(index + 1);
    layout.pattern = LayoutPattern(sheet, slots, layout.cells, name);
    BuildCodebook(sheet, o.symmetry_tolerance_mm, &layout);
  }
  return sheet;
}

namespace {

// mm to 0.1 mm, without a "-0.0".
std::string TenthMm(double v) {
  const double rounded = std::round(v * 10.0) / 10.0;
  return FormatFixed(rounded == 0.0 ? 0.0 : rounded, 1);
}

std::string Header(const ImportedLayout& layout, const SheetImport& sheet) {
  std::string ids;
  for (int c : layout.cells) {
    if (!ids.empty()) ids += ", ";
    ids += std::to_string(sheet.cells[c].index);
  }
  std::string out = "# Imported by patlab import from " +
                    std::filesystem::path(sheet.file).filename().string() +
                    ": positions measured by segmentation.\n# Cells (IDs): " + ids + ".\n";
  int height = 0;
  for (int c : layout.cells) height = std::max(height, sheet.cells[c].height_mm);
  if (height > 0)
    out += "# Robot height from the sheet's yellow bar: " + std::to_string(height) + " mm.\n";
  if (!sheet.sector_bounds_deg.empty()) {
    out += "# Ring sectors bounded at";
    for (double a : sheet.sector_bounds_deg) out.append(" ").append(FormatFixed(a, 1));
    out +=
        " deg (0 = front, 90 = left);\n# each sector modelled as the largest disc about its "
        "centroid inside it (docs/import.md).\n";
  }
  return out;
}

}  // namespace

std::string PatternFileText(const ImportedLayout& layout, const SheetImport& sheet) {
  const Pattern& p = layout.pattern;
  std::string out = Header(layout, sheet);
  out += "name = \"" + p.name + "\"\n";
  out += "description = \"" + std::to_string(p.size() - 1) +
         (sheet.sector_bounds_deg.empty() ? " dots" : " ring sectors (as discs)") +
         " around a blue key, from " + std::filesystem::path(sheet.file).filename().string() +
         "\"\n";
  for (const Patch& patch : p.patches) {
    out += "\n[[patch]]\nrole = \"" + std::string(patch.role == PatchRole::kKey ? "key" : "id") +
           "\"\nx = " + TenthMm(patch.position_mm.x()) + "\ny = " + TenthMm(patch.position_mm.y()) +
           "\nradius = " + TenthMm(patch.radius_mm) + "\n";
  }
  return out;
}

std::string CodebookFileText(const ImportedLayout& layout, const SheetImport& sheet) {
  const detect::Codebook& book = layout.codebook;
  std::string out = Header(layout, sheet);
  for (const auto& [id, why] : layout.dropped) {
    out += "# ID " + std::to_string(id) + " left out: " + why + ".\n";
  }
  out += "pattern = \"" + book.pattern + "\"\ncolours = [";
  for (size_t c = 0; c < book.colours.size(); ++c) {
    out += (c ? ", \"" : "\"") + book.colours[c] + "\"";
  }
  out += "]\n";
  for (const detect::CodebookEntry& e : book.entries) {
    out += "\n[[id]]\nid = " + std::to_string(e.id) + "\nslots = [";
    for (size_t k = 0; k < e.colour.size(); ++k) {
      out += (k ? ", \"" : "\"") + book.colours[e.colour[k]] + "\"";
    }
    out += "]\n";
  }
  return out;
}

}  // namespace patlab::design

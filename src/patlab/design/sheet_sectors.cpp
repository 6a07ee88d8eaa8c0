// Ring-sector sheets (the KIKS design): sectors found by angle around the key, each modelled as a
// disc patch at its centroid. See sheet_import_internal.h and docs/import.md.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/design/sheet_import_internal.h"

namespace patlab::design::internal {

namespace {

constexpr double kBoundaryToleranceDeg = 5.0;  // colour changes this close are one boundary
constexpr double kClearanceMm = 0.5;           // a sector's disc keeps this far inside it
constexpr int kMinBinPixels = 3;

// Calls fn(model position mm, model angle in [0, 360) degrees, class) for every dot-coloured
// pixel of the key's cell within kReachMm of the key (a neighbour cell's ring can be nearer).
template <typename Fn>
void ForRingPixels(const vision::Segmenter& seg, const Vec2& key_px, const SheetImportOptions& o,
                   Fn fn) {
  const double reach_px = kReachMm / o.mm_per_px;
  const int cx = static_cast<int>(std::floor(key_px.x() / o.cell_px)) * o.cell_px;
  const int cy = static_cast<int>(std::floor(key_px.y() / o.cell_px)) * o.cell_px;
  const int x0 = std::max(cx, static_cast<int>(std::floor(key_px.x() - reach_px)));
  const int x1 = std::min({seg.width_px(), cx + o.cell_px,
                           static_cast<int>(std::ceil(key_px.x() + reach_px)) + 1}) -
                 1;
  const int y0 = std::max(cy, static_cast<int>(std::floor(key_px.y() - reach_px)));
  const int y1 = std::min({seg.height_px(), cy + o.cell_px,
                           static_cast<int>(std::ceil(key_px.y() + reach_px)) + 1}) -
                 1;
  const std::vector<uint8_t>& classes = seg.class_image();
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const int c = classes[static_cast<size_t>(y) * seg.width_px() + x] - 1;
      if (c < 1 || c >= kYellow) continue;
      const Vec2 d = (Vec2(x, y) - key_px) * o.mm_per_px;
      if (d.norm() > kReachMm) continue;
      const Vec2 m(-d.y(), -d.x());  // image up is the model's +x, image left its +y
      double angle = std::atan2(m.y(), m.x()) * 180.0 / std::numbers::pi;
      if (angle < 0.0) angle += 360.0;
      fn(m, std::min(angle, 359.999), c);
    }
  }
}

// Degrees from a to b counter-clockwise, in [0, 360).
double Ccw(double a, double b) {
  const double d = std::fmod(b - a, 360.0);
  return d < 0.0 ? d + 360.0 : d;
}

std::vector<double> Boundaries(const std::vector<CellRing>& rings) {
  std::vector<double> sum, first;
  std::vector<int> count;
  for (const CellRing& ring : rings) {
    for (int b = 0; b < 360; ++b) {
      if (ring.colour[b] == ring.colour[(b + 359) % 360]) continue;
      size_t k = 0;
      while (k < first.size() &&
             std::min(Ccw(first[k], b), Ccw(b, first[k])) > kBoundaryToleranceDeg) {
        ++k;
      }
      if (k == first.size()) {
        first.push_back(b);
        sum.push_back(0.0);
        count.push_back(0);
      }
      // Angles near the first one of the cluster, unwrapped around it.
      const double offset = Ccw(first[k], b) <= 180.0 ? Ccw(first[k], b) : -Ccw(b, first[k]);
      sum[k] += offset;
      ++count[k];
    }
  }
  std::vector<double> bounds;
  for (size_t k = 0; k < first.size(); ++k) {
    bounds.push_back(std::fmod(first[k] + sum[k] / count[k] + 360.0, 360.0));
  }
  std::sort(bounds.begin(), bounds.end());
  return bounds;
}

// The colour the ring gives the sector from a0 to a1 (ccw): the majority class of its bins, one
// bin in from each boundary, when it holds at least half of them; else -1 (no sector there).
int SectorColour(const CellRing& ring, double a0, double a1) {
  std::array<int, kYellow> votes{};
  int bins = 0;
  const int first = static_cast<int>(std::ceil(a0)) + 1;
  const int width = static_cast<int>(std::floor(Ccw(a0, a1))) - 2;
  for (int k = 0; k < width; ++k) {
    const int c = ring.colour[(first + k) % 360];
    ++bins;
    if (c > 0) ++votes[c];
  }
  const auto best = std::max_element(votes.begin(), votes.end());
  return bins > 0 && 2 * *best >= bins ? static_cast<int>(best - votes.begin()) : -1;
}

// The disc patch of one coloured sector: the centroid of its pixels; the radius of the largest
// disc about the centroid inside the sector (its two edges, the key, the outer rim), less the
// clearance.
SheetDot SectorDot(const vision::Segmenter& seg, const CellRing& ring, double key_radius_mm,
                   double a0, double a1, int colour, const SheetImportOptions& o) {
  Vec2 sum = Vec2::Zero();
  double count = 0.0, outer = 0.0;
  ForRingPixels(seg, ring.key_px, o, [&](const Vec2& m, double angle, int c) {
    if (c != colour || Ccw(a0, angle) >= Ccw(a0, a1)) return;
    sum += m;
    count += 1.0;
    outer = std::max(outer, m.norm());
  });
  const Vec2 centre = sum / count;
  double phi = std::atan2(centre.y(), centre.x()) * 180.0 / std::numbers::pi;
  if (phi < 0.0) phi += 360.0;
  const double d = centre.norm();
  const double edge_deg = std::min(Ccw(a0, phi), Ccw(phi, a1));
  const double to_edge = edge_deg >= 90.0 ? d : d * std::sin(edge_deg * std::numbers::pi / 180.0);
  const double radius = std::min({to_edge, outer - d, d - key_radius_mm}) - kClearanceMm;
  return {centre, std::max(radius, 0.0), kClassNames[colour], -1};
}

}  // namespace

bool HasRingSectors(const vision::Segmenter& seg, const vision::Region& key,
                    const SheetImportOptions& o) {
  const double mm2_per_px = o.mm_per_px * o.mm_per_px;
  for (int c = 1; c < kYellow; ++c) {
    for (const vision::Region& r : seg.RegionsOf(c)) {
      if (r.area_px * mm2_per_px <= kDotAreaMaxMm2) continue;
      const bool same_cell =
          std::floor(r.centroid_px.x() / o.cell_px) ==
              std::floor(key.centroid_px.x() / o.cell_px) &&
          std::floor(r.centroid_px.y() / o.cell_px) == std::floor(key.centroid_px.y() / o.cell_px);
      if (same_cell && (r.centroid_px - key.centroid_px).norm() * o.mm_per_px <= kReachMm) {
        return true;
      }
    }
  }
  return false;
}

CellRing ReadRing(const vision::Segmenter& seg, const vision::Region& key,
                  const SheetImportOptions& o) {
  CellRing ring;
  ring.key_px = key.centroid_px;
  std::vector<std::array<int, kYellow>> votes(360, std::array<int, kYellow>{});
  ForRingPixels(seg, ring.key_px, o, [&](const Vec2& /*m*/, double angle, int c) {
    ++votes[static_cast<int>(angle)][c];
  });
  for (int b = 0; b < 360; ++b) {
    const auto best = std::max_element(votes[b].begin(), votes[b].end());
    ring.colour[b] = *best >= kMinBinPixels ? static_cast<int>(best - votes[b].begin()) : -1;
  }
  return ring;
}

void SplitRings(const vision::Segmenter& seg, const std::vector<CellRing>& rings,
                const SheetImportOptions& o, SheetImport* sheet) {
  const std::vector<double> bounds = Boundaries(rings);
  if (bounds.size() < 2) {
    throw InputError(sheet->file +
                     ": ring sectors without a boundary; expected sectors of different colours "
                     "(or ring gaps) in at least one cell");
  }
  sheet->sector_bounds_deg = bounds;
  for (const CellRing& ring : rings) {
    SheetCell& cell = sheet->cells[ring.cell];
    cell.dots.clear();
    for (size_t k = 0; k < bounds.size(); ++k) {
      const double a0 = bounds[k], a1 = bounds[(k + 1) % bounds.size()];
      const int colour = SectorColour(ring, a0, a1);
      if (colour < 1) continue;
      cell.dots.push_back(SectorDot(seg, ring, cell.key_radius_mm, a0, a1, colour, o));
    }
  }
}

}  // namespace patlab::design::internal

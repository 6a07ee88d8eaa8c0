// Pieces of the layout search shared by its source files: design.cpp (the symmetry and the
// search), design_check.cpp (the options' checks), design_metrics.cpp (the criteria of a layout)
// and design_report.cpp (the report and the pattern file). Not part of the public API: include
// design.h instead.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "patlab/core/format.h"
#include "patlab/core/pattern.h"
#include "patlab/design/design.h"

namespace patlab::design::internal {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
// The geometric constraints hold to within the precision of the file, 1e-3 mm: the layout is
// rounded to it (a move of at most 0.71e-3 mm per patch), and a ring exactly as wide as a dot
// plus the gap (the SSL robot top with a 5 mm rim) leaves no room for a margin on both sides.
// The local search keeps a little inside each limit so that most of that tolerance is spare.
inline constexpr double kGeometryToleranceMm = 1e-3;
inline constexpr double kSafetyMm = 0.0;
// The criteria limits likewise (COBYLA ends on an active constraint within about its final trust
// radius, xtol_mm): onset in mm, the angle CRLB in mrad/mm, the position CRLB in mm/mm.
inline constexpr double kSafetyOnsetMm = 1e-3;
inline constexpr double kSafetyAngle = 1e-4;
inline constexpr double kSafetyPosition = 1e-6;
// Criteria that are infinite (no wrong rotation to reject) enter the search clamped to this.
inline constexpr double kLargeMm = 1e3;
inline constexpr uint32_t kStartStream = 0x64657369u;  // "desi": the random start layouts

inline double IdRadius(const DesignOptions& o, int i) {
  return o.id_radii_mm.size() == 1 ? o.id_radii_mm[0] : o.id_radii_mm[i];
}
// The largest patch-centre radius plus patch radius allowed (mm).
inline double InnerRadius(const DesignOptions& o) {
  return 0.5 * o.outer_diameter_mm - o.rim_gap_mm;
}

inline uint64_t MaxIds(const DesignOptions& o) {
  uint64_t n = 1;
  for (int i = 0; i < o.id_patches; ++i) n *= static_cast<uint64_t>(o.palette);
  return n;
}
inline uint64_t RequiredIds(const DesignOptions& o) {
  return o.min_ids == 0 ? MaxIds(o) : static_cast<uint64_t>(o.min_ids);
}

inline std::string Mm(double v) { return FormatFixed(v, 3); }

// The criteria of a layout, and how deep inside the tolerance the nearest accepted wrong shift
// lies (mm; <= 0 when geometry rejects every wrong rotation): the continuous measure the search
// uses to move out of an ID-losing symmetry.
struct LayoutEvaluation {
  DesignMetrics metrics;
  double accepted_depth_mm = 0.0;
  // The onset (mm) of each wrong rotation, shifts 1 .. m - 1 of the circular order; +inf for a
  // shift that colours decide. The minimum is metrics.rotation_onset_mm; each one alone is a
  // smooth function of the layout, which the search needs (their minimum is not).
  std::vector<double> shift_onset_mm;
};

// The criteria of `pattern` under the options, the detector's chi-square threshold `chi2`
// (design_metrics.cpp).
LayoutEvaluation EvaluateLayout(const Pattern& pattern, const DesignOptions& o, double chi2);

}  // namespace patlab::design::internal

// The design's report and its pattern file (DesignReportText, DesignPatternFileText).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/design.h"
#include "patlab/design/design_internal.h"

namespace patlab::design {

using internal::Mm;
using internal::RequiredIds;

namespace {

std::string Criterion(double v, int decimals) {
  if (std::isinf(v)) return "inf";
  // A value that rounds to zero (a patch 1e-5 mm inside the rim) prints as 0, not -0.
  return FormatFixed(std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v, decimals);
}

std::string OptionsLines(const DesignOptions& o, const std::string& prefix) {
  std::string radii;
  for (double r : o.id_radii_mm) {
    if (!radii.empty()) radii += ",";
    radii += FormatNumber(r);
  }
  std::string out;
  out += prefix + "constraints: outer_diameter_mm " + FormatNumber(o.outer_diameter_mm) +
         ", rim_gap_mm " + FormatNumber(o.rim_gap_mm) + ", key_radius_mm " +
         FormatNumber(o.key_radius_mm) + ", id_patches " + std::to_string(o.id_patches) +
         ", id_radii_mm " + radii + ", min_gap_mm " + FormatNumber(o.min_gap_mm) + ", palette " +
         std::to_string(o.palette) + ", tolerance_mm " + FormatNumber(o.tolerance_mm) + "\n";
  out += prefix + "objective: minimise " + std::string(NameOf(o.objective, kDesignObjectiveNames)) +
         " subject to ids >= " + std::to_string(RequiredIds(o)) +
         ", rotation_onset_mm >= " + FormatNumber(o.min_rotation_onset_mm) +
         ", angle_crlb_mrad_per_mm <= " + FormatNumber(o.max_angle_crlb_mrad_per_mm) +
         ", position_crlb_per_mm <= " + FormatNumber(o.max_position_crlb_per_mm) + "\n";
  out += prefix + "search: NLopt COBYLA from " + std::to_string(o.starts) +
         " seeded starts, max_evaluations " + std::to_string(o.max_evaluations) + ", xtol_mm " +
         FormatNumber(o.xtol_mm) + ", seed " + std::to_string(o.seed) +
         (o.symmetry == DesignSymmetry::kNone
              ? std::string()
              : ", symmetry " + std::string(NameOf(o.symmetry, kDesignSymmetryNames))) +
         "\n";
  return out;
}

std::string MetricsLine(const DesignMetrics& m) {
  return "angle CRLB " + Criterion(m.angle_crlb_mrad_per_mm, 3) + " mrad/mm, position CRLB " +
         Criterion(m.position_crlb_per_mm, 4) + " mm/mm, IDs " + std::to_string(m.ids) +
         ", rotations " + std::to_string(m.rotations) + ", rotation sigma0/onset " +
         Criterion(m.rotation_sigma0_mm, 2) + "/" + Criterion(m.rotation_onset_mm, 2) +
         " mm, smallest gap " + Criterion(m.min_gap_mm, 3) + " mm, rim gap " +
         Criterion(m.rim_gap_mm, 3) + " mm";
}

}  // namespace

std::string DesignPatternFileText(const DesignResult& result) {
  const Pattern& p = result.pattern;
  std::string out = "# Designed by patlab design (docs/design.md).\n";
  out += OptionsLines(result.options, "# ");
  out += "# result: " + MetricsLine(result.metrics) + "\n";
  out += "name = \"" + p.name + "\"\n";
  out += "description = \"" + p.description + "\"\n";
  for (const Patch& patch : p.patches) {
    out += "\n[[patch]]\nrole = \"" + std::string(NameOf(patch.role, kPatchRoleNames)) +
           "\"\nx = " + Mm(patch.position_mm.x()) + "\ny = " + Mm(patch.position_mm.y()) +
           "\nradius = " + Mm(patch.radius_mm) + "\n";
  }
  return out;
}

std::string DesignReportText(const DesignResult& r) {
  std::string out = "Design " + r.pattern.name + "\n" + OptionsLines(r.options, "");
  out += "\nbest (start " + std::to_string(r.best_start) + "): " + MetricsLine(r.metrics) + "\n";
  out += "patches (mm):\n";
  for (const Patch& patch : r.pattern.patches) {
    out += "  " + std::string(NameOf(patch.role, kPatchRoleNames)) + "  x " +
           Mm(patch.position_mm.x()) + "  y " + Mm(patch.position_mm.y()) + "  radius " +
           Mm(patch.radius_mm) + "  (r " + Mm(patch.position_mm.norm()) + ", angle " +
           FormatFixed(
               std::atan2(patch.position_mm.y(), patch.position_mm.x()) * 180.0 / std::numbers::pi,
               2) +
           " deg)\n";
  }
  out += "\nstarts (objective " + std::string(NameOf(r.options.objective, kDesignObjectiveNames)) +
         "; start -> end):\n";
  out +=
      "start  evals  nlopt  angle mrad/mm    pos mm/mm          IDs      onset mm       "
      "feasible\n";
  for (const DesignStart& s : r.starts) {
    out += StringPrintf("%-5d  %-5d  %-5d  ", s.start, s.evaluations, s.nlopt_result);
    out += Criterion(s.initial.angle_crlb_mrad_per_mm, 3) + "->" +
           Criterion(s.final.angle_crlb_mrad_per_mm, 3) + "  " +
           Criterion(s.initial.position_crlb_per_mm, 4) + "->" +
           Criterion(s.final.position_crlb_per_mm, 4) + "  " + std::to_string(s.initial.ids) +
           "->" + std::to_string(s.final.ids) + "  " + Criterion(s.initial.rotation_onset_mm, 2) +
           "->" + Criterion(s.final.rotation_onset_mm, 2) + "  " +
           (s.final.feasible ? "yes" : "no: " + s.final.violated) +
           (s.from_options ? "  (given start)" : "") + "\n";
  }
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "\n" + std::string
  // here.
  out += "\n";
  out += std::to_string(r.evaluations) + " layouts evaluated\n";
  return out;
}

}  // namespace patlab::design

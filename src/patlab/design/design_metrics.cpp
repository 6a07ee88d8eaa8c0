// The criteria of a layout (EvaluateDesign, and the search's evaluation of each layout it tries):
// geometry, IDs, the rotation fix as patlab compare computes it, and the first violated limit.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/compare.h"
#include "patlab/design/design.h"
#include "patlab/design/design_internal.h"
#include "patlab/detect/codebook.h"
#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"

namespace patlab::design {

using internal::EvaluateLayout;
using internal::kGeometryToleranceMm;
using internal::kInf;
using internal::kLargeMm;
using internal::LayoutEvaluation;
using internal::Mm;
using internal::RequiredIds;

namespace {

void CheckGeometry(const Pattern& pattern, const DesignOptions& o, DesignMetrics* m) {
  m->min_gap_mm = kInf;
  double reach = 0.0;
  for (int i = 0; i < pattern.size(); ++i) {
    const Patch& p = pattern.patches[i];
    reach = std::max(reach, p.position_mm.norm() + p.radius_mm);
    for (int j = 0; j < i; ++j) {
      const Patch& q = pattern.patches[j];
      m->min_gap_mm = std::min(m->min_gap_mm,
                               (p.position_mm - q.position_mm).norm() - p.radius_mm - q.radius_mm);
    }
  }
  m->rim_gap_mm = 0.5 * o.outer_diameter_mm - reach;
}

// The first violated constraint, in the order geometry, IDs, onset, angle, position.
std::string Violation(const DesignMetrics& m, const DesignOptions& o) {
  if (m.rim_gap_mm < o.rim_gap_mm - kGeometryToleranceMm) {
    return "a patch " + Mm(m.rim_gap_mm) +
           " mm from the rim; expected rim_gap_mm >= " + FormatNumber(o.rim_gap_mm);
  }
  if (m.min_gap_mm < o.min_gap_mm - kGeometryToleranceMm) {
    return "two patches " + Mm(m.min_gap_mm) +
           " mm apart; expected min_gap_mm >= " + FormatNumber(o.min_gap_mm);
  }
  if (m.ids < RequiredIds(o)) {
    return std::to_string(m.ids) + " IDs; expected min_ids >= " + std::to_string(RequiredIds(o));
  }
  if (m.rotation_onset_mm < o.min_rotation_onset_mm) {
    return "rotation onset " + Mm(m.rotation_onset_mm) +
           " mm; expected min_rotation_onset_mm >= " + FormatNumber(o.min_rotation_onset_mm);
  }
  if (m.angle_crlb_mrad_per_mm > o.max_angle_crlb_mrad_per_mm) {
    return "angle CRLB " + Mm(m.angle_crlb_mrad_per_mm) +
           " mrad/mm; expected max_angle_crlb_mrad_per_mm <= " +
           FormatNumber(o.max_angle_crlb_mrad_per_mm);
  }
  if (m.position_crlb_per_mm > o.max_position_crlb_per_mm) {
    return "position CRLB " + FormatFixed(m.position_crlb_per_mm, 5) +
           " mm/mm; expected max_position_crlb_per_mm <= " +
           FormatNumber(o.max_position_crlb_per_mm);
  }
  return "";
}

// The rotation fix as patlab compare computes it (design/compare.h ComputeDesignGeometry, from its
// own pieces): the shifts that neither ID colours nor fixed colours decide, their noise-free
// error E0 and onset; `chi2` is DetectorChiSquared of the pattern (the same for every layout of
// one size, so the search computes it once).
void RotationFix(const Pattern& pattern, const detect::Symmetry& symmetry, double chi2,
                 LayoutEvaluation* e) {
  const auto& effective = symmetry.effective_shifts;
  const int dof = 2 * pattern.size() - 3;
  double e0 = kInf;
  e->shift_onset_mm.clear();
  for (const detect::ShiftFit& fit : symmetry.fits) {
    if (fit.shift == 0) continue;
    const bool by_colours =
        std::find(effective.begin(), effective.end(), fit.shift) != effective.end() ||
        !fit.preserves_roles;
    double onset = kInf;
    if (!by_colours) {
      const double e0_shift = WrongRotationError(pattern, symmetry, fit.shift);
      e0 = std::min(e0, e0_shift);
      onset = RotationOnsetSigma(e0_shift, dof, chi2);
    }
    e->shift_onset_mm.push_back(onset);
  }
  DesignMetrics& m = e->metrics;
  m.rotation_sigma0_mm = std::isinf(e0) ? kInf : std::sqrt(e0 / chi2);
  m.rotation_onset_mm = std::isinf(e0) ? kInf : RotationOnsetSigma(e0, dof, chi2);
}

// A layout the search may try with two patch centres on one point: the estimators' model (and
// so the bound) is undefined there; such a layout gets the worst finite criteria instead.
bool HasCoincidentPatches(const Pattern& pattern) {
  for (int i = 0; i < pattern.size(); ++i) {
    for (int j = 0; j < i; ++j) {
      if ((pattern.patches[i].position_mm - pattern.patches[j].position_mm).norm() < 1e-6) {
        return true;
      }
    }
  }
  return false;
}

LayoutEvaluation CoincidentLayout(const Pattern& pattern, const DesignOptions& o) {
  LayoutEvaluation e;
  DesignMetrics& m = e.metrics;
  m.angle_crlb_mrad_per_mm = m.position_crlb_per_mm = kLargeMm;
  m.rotation_onset_mm = m.rotation_sigma0_mm = 0.0;
  e.accepted_depth_mm = o.tolerance_mm;
  e.shift_onset_mm.assign(pattern.size() - 2, 0.0);
  CheckGeometry(pattern, o, &m);
  m.violated = Violation(m, o);
  m.feasible = false;
  return e;
}

}  // namespace

namespace internal {

LayoutEvaluation EvaluateLayout(const Pattern& pattern, const DesignOptions& o, double chi2) {
  if (HasCoincidentPatches(pattern)) return CoincidentLayout(pattern, o);
  LayoutEvaluation e;
  DesignMetrics& m = e.metrics;
  const estimate::StdPerSigma crlb =
      estimate::CramerRaoBound(estimate::Model::FromPattern(pattern));
  m.angle_crlb_mrad_per_mm = 1e3 * crlb.theta;
  m.position_crlb_per_mm = crlb.position_per_axis;
  const detect::Symmetry symmetry = detect::FindSymmetry(pattern, o.tolerance_mm);
  m.ids = detect::CountIds(pattern, symmetry, o.palette);
  m.rotations = symmetry.effective_order();
  RotationFix(pattern, symmetry, chi2, &e);
  e.accepted_depth_mm = -kInf;
  for (const detect::ShiftFit& fit : symmetry.fits) {
    if (fit.shift != 0 && fit.accepted) {
      e.accepted_depth_mm = std::max(e.accepted_depth_mm, o.tolerance_mm - fit.residual_mm);
    }
  }
  CheckGeometry(pattern, o, &m);
  m.violated = Violation(m, o);
  m.feasible = m.violated.empty();
  return e;
}

}  // namespace internal

DesignMetrics EvaluateDesign(const Pattern& pattern, const DesignOptions& options) {
  return EvaluateLayout(pattern, options, DetectorChiSquared(pattern, options.tolerance_mm))
      .metrics;
}

}  // namespace patlab::design

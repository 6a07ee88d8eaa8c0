#include "patlab/design/design.h"

#include <nlopt.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/design/compare.h"
#include "patlab/detect/codebook.h"
#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"
#include "patlab/io/csv.h"

namespace patlab::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The geometric constraints hold to within the precision of the file, 1e-3 mm: the layout is
// rounded to it (a move of at most 0.71e-3 mm per patch), and a ring exactly as wide as a dot
// plus the gap (the SSL robot top with a 5 mm rim) leaves no room for a margin on both sides.
// The local search keeps a little inside each limit so that most of that tolerance is spare.
constexpr double kGeometryToleranceMm = 1e-3;
constexpr double kSafetyMm = 0.0;
// The criteria limits likewise (COBYLA ends on an active constraint within about its final trust
// radius, xtol_mm): onset in mm, the angle CRLB in mrad/mm, the position CRLB in mm/mm.
constexpr double kSafetyOnsetMm = 1e-3;
constexpr double kSafetyAngle = 1e-4;
constexpr double kSafetyPosition = 1e-6;
// Criteria that are infinite (no wrong rotation to reject) enter the search clamped to this.
constexpr double kLargeMm = 1e3;
constexpr uint32_t kStartStream = 0x64657369u;  // "desi": the random start layouts

double IdRadius(const DesignOptions& o, int i) {
  return o.id_radii_mm.size() == 1 ? o.id_radii_mm[0] : o.id_radii_mm[i];
}
// The largest patch-centre radius plus patch radius allowed (mm).
double InnerRadius(const DesignOptions& o) { return 0.5 * o.outer_diameter_mm - o.rim_gap_mm; }

uint64_t MaxIds(const DesignOptions& o) {
  uint64_t n = 1;
  for (int i = 0; i < o.id_patches; ++i) n *= static_cast<uint64_t>(o.palette);
  return n;
}
uint64_t RequiredIds(const DesignOptions& o) {
  return o.min_ids == 0 ? MaxIds(o) : static_cast<uint64_t>(o.min_ids);
}

std::string Mm(double v) { return FormatFixed(v, 3); }

// The geometric impossibilities that no search can fix (checked once every field is in range).
void CheckFits(const DesignOptions& o, OptionsChecker* check) {
  const double inner = InnerRadius(o);
  if (o.key_radius_mm > inner) {
    check->Require("key_radius_mm", o.key_radius_mm, false,
                   "at most outer_diameter_mm / 2 - rim_gap_mm = " + FormatNumber(inner) +
                       " (the key patch must fit in the robot top)");
    return;
  }
  const double ring = 0.5 * (inner - o.key_radius_mm - o.min_gap_mm);
  for (int i = 0; i < static_cast<int>(o.id_radii_mm.size()); ++i) {
    check->Require("id_radii_mm", o.id_radii_mm[i], o.id_radii_mm[i] <= ring,
                   "at most (outer_diameter_mm / 2 - rim_gap_mm - key_radius_mm - min_gap_mm) / 2"
                   " = " +
                       FormatNumber(ring) +
                       " (an ID patch must fit between the key patch and the rim)");
  }
  if (!check->problems().empty()) return;
  // Necessary for any layout: the discs of radius r_i + gap/2 are disjoint, lie inside the disc
  // of radius inner + gap/2 and outside the key's disc of radius r_key + gap/2.
  const double half_gap = 0.5 * o.min_gap_mm;
  const double room = std::pow(inner + half_gap, 2) - std::pow(o.key_radius_mm + half_gap, 2);
  double need = 0.0;
  for (int i = 0; i < o.id_patches; ++i) need += std::pow(IdRadius(o, i) + half_gap, 2);
  if (need > room) {
    check->Require("id_patches", o.id_patches, false,
                   "fewer ID patches of these radii: with half of min_gap_mm around each they "
                   "cover " +
                       FormatFixed(std::numbers::pi * need, 0) + " mm^2, more than the " +
                       FormatFixed(std::numbers::pi * room, 0) +
                       " mm^2 between the key patch and the rim");
  }
}

// A cyclic family accepts every rotation by 360/id_patches: its ID capacity is that of the regular
// layout (the same for every member), counted once before the search.
void CheckCyclic(const DesignOptions& o, OptionsChecker* check) {
  const double rho = 0.5 * (o.key_radius_mm + o.min_gap_mm + InnerRadius(o));
  const double x[2] = {rho, 0.0};
  const Pattern regular = DesignPattern(o, ExpandSymmetry(o, x));
  const uint64_t ids =
      detect::CountIds(regular, detect::FindSymmetry(regular, o.tolerance_mm), o.palette);
  if (RequiredIds(o) > ids) {
    check->Fail("min_ids", "symmetry cyclic leaves " + std::to_string(ids) + " IDs with " +
                               std::to_string(o.palette) +
                               " colours; expected min_ids <= " + std::to_string(ids) +
                               " (0 asks for all " + std::to_string(MaxIds(o)) + ")");
  }
}

}  // namespace

std::vector<OptionsProblem> Check(const DesignOptions& o) {
  OptionsChecker check;
  const bool name_ok =
      !o.name.empty() && o.name.size() <= 100 &&
      std::all_of(o.name.begin(), o.name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
      });
  if (!name_ok) {
    check.Fail("name",
               "name is \"" + o.name + "\"; expected 1 to 100 letters, digits, '-', '_' or '.'");
  }
  check.Positive("outer_diameter_mm", o.outer_diameter_mm, "mm")
      .NonNegative("rim_gap_mm", o.rim_gap_mm, "mm")
      .Positive("key_radius_mm", o.key_radius_mm, "mm")
      .IntegerInRange("id_patches", o.id_patches, 1, kMaxPatches - 1)
      .NonNegative("min_gap_mm", o.min_gap_mm, "mm")
      .IntegerInRange("palette", o.palette, 2, 8)
      .NonNegative("tolerance_mm", o.tolerance_mm, "mm")
      .NonNegative("min_rotation_onset_mm", o.min_rotation_onset_mm, "mm")
      .Require("max_angle_crlb_mrad_per_mm", o.max_angle_crlb_mrad_per_mm,
               o.max_angle_crlb_mrad_per_mm > 0, "a number > 0 or inf (mrad/mm)")
      .Require("max_position_crlb_per_mm", o.max_position_crlb_per_mm,
               o.max_position_crlb_per_mm > 0, "a number > 0 or inf (mm/mm)")
      .IntegerInRange("starts", o.starts, 1, 100000)
      .IntegerInRange("max_evaluations", o.max_evaluations, 10, 10000000)
      .Positive("xtol_mm", o.xtol_mm, "mm");
  const bool count_ok = o.id_patches >= 1 && o.id_patches < kMaxPatches;
  if (count_ok && o.palette >= 2 && o.palette <= 8) {
    check.IntegerInRange("min_ids", o.min_ids, 0, static_cast<int64_t>(MaxIds(o)));
  }
  if (o.id_radii_mm.size() != 1 && (!count_ok || o.id_radii_mm.size() != size_t(o.id_patches))) {
    check.Fail("id_radii_mm", "id_radii_mm has " + std::to_string(o.id_radii_mm.size()) +
                                  " values; expected 1 or id_patches (" +
                                  std::to_string(o.id_patches) + ")");
  }
  for (double r : o.id_radii_mm) check.Positive("id_radii_mm", r, "mm");
  if (!o.start_mm.empty() && o.start_mm.size() != size_t(o.id_patches)) {
    check.Fail("start_mm", "start_mm has " + std::to_string(o.start_mm.size()) +
                               " positions; expected none or id_patches (" +
                               std::to_string(o.id_patches) + ")");
  }
  if (check.problems().empty()) CheckFits(o, &check);
  if (check.problems().empty() && o.symmetry == DesignSymmetry::kCyclic) CheckCyclic(o, &check);
  return check.Take();
}

void Validate(const DesignOptions& options) { ThrowFirstProblem(Check(options)); }

Pattern DesignPattern(const DesignOptions& o, const std::vector<Vec2>& id_positions_mm) {
  PATLAB_CHECK(static_cast<int>(id_positions_mm.size()) == o.id_patches);
  Pattern p;
  p.name = o.name;
  p.description = "designed by patlab design: key + " + std::to_string(o.id_patches) +
                  " ID patches in a " + FormatNumber(o.outer_diameter_mm) + " mm robot top";
  p.patches.push_back({Vec2::Zero(), o.key_radius_mm, PatchRole::kKey, ""});
  for (int i = 0; i < o.id_patches; ++i) {
    p.patches.push_back({id_positions_mm[i], IdRadius(o, i), PatchRole::kId, ""});
  }
  p.key_index = 0;
  p.orientation_pairs = DefaultOrientationPairs(p.patches, p.key_index);
  return p;
}

int SymmetryVariables(const DesignOptions& o) {
  switch (o.symmetry) {
    case DesignSymmetry::kNone:
      break;
    case DesignSymmetry::kMirror:
      return 2 * (o.id_patches / 2) + o.id_patches % 2;
    case DesignSymmetry::kCyclic:
      return 2;
  }
  return 2 * o.id_patches;
}

std::vector<Vec2> ExpandSymmetry(const DesignOptions& o, const double* x) {
  const int n = o.id_patches;
  std::vector<Vec2> p(n);
  switch (o.symmetry) {
    case DesignSymmetry::kNone:
      for (int i = 0; i < n; ++i) p[i] = Vec2(x[2 * i], x[2 * i + 1]);
      break;
    case DesignSymmetry::kMirror:
      for (int i = 0; i < n / 2; ++i) {
        p[i] = Vec2(x[2 * i], x[2 * i + 1]);
        p[n / 2 + i] = Vec2(x[2 * i], -x[2 * i + 1]);
      }
      if (n % 2 == 1) p[n - 1] = Vec2(x[n - 1], 0.0);
      break;
    case DesignSymmetry::kCyclic:
      for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n, c = std::cos(a), sn = std::sin(a);
        p[i] = Vec2(c * x[0] - sn * x[1], sn * x[0] + c * x[1]);
      }
      break;
  }
  return p;
}

std::vector<double> ReduceSymmetry(const DesignOptions& o, const std::vector<Vec2>& layout) {
  PATLAB_CHECK(static_cast<int>(layout.size()) == o.id_patches);
  const int free = o.symmetry == DesignSymmetry::kNone     ? o.id_patches
                   : o.symmetry == DesignSymmetry::kCyclic ? 1
                                                           : o.id_patches / 2;
  std::vector<double> x;
  for (int i = 0; i < free; ++i) {
    x.push_back(layout[i].x());
    x.push_back(layout[i].y());
  }
  // Mirror, odd count: the last patch moved onto the axis at its distance from the key.
  if (o.symmetry == DesignSymmetry::kMirror && o.id_patches % 2 == 1) {
    const Vec2& q = layout.back();
    x.push_back(q.x() < 0.0 ? -q.norm() : q.norm());
  }
  return x;
}

namespace {

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

}  // namespace

DesignMetrics EvaluateDesign(const Pattern& pattern, const DesignOptions& options) {
  return EvaluateLayout(pattern, options, DetectorChiSquared(pattern, options.tolerance_mm))
      .metrics;
}

namespace {

// One local run's state: the options, and the last layout evaluated (NLopt asks for the
// objective and the constraints of the same point one after the other).
struct SearchContext {
  const DesignOptions* options = nullptr;
  double chi2 = 0.0;  // DetectorChiSquared of every layout of these options
  std::vector<double> last_x;
  LayoutEvaluation last;
  int evaluations = 0;
};

// The search variables: x, y of each ID patch, then (objective rotation_onset) the epigraph
// variable t <= every shift's onset, which the search maximises: max-min made smooth.
bool HasEpigraph(const DesignOptions& o) { return o.objective == DesignObjective::kRotationOnset; }
int NumVariables(const DesignOptions& o) { return SymmetryVariables(o) + (HasEpigraph(o) ? 1 : 0); }

const LayoutEvaluation& Evaluate(SearchContext* c, const double* x) {
  const int n = SymmetryVariables(*c->options);
  if (c->evaluations == 0 || !std::equal(c->last_x.begin(), c->last_x.end(), x)) {
    c->last_x.assign(x, x + n);
    c->last = EvaluateLayout(DesignPattern(*c->options, ExpandSymmetry(*c->options, x)),
                             *c->options, c->chi2);
    ++c->evaluations;
  }
  return c->last;
}

double Objective(unsigned /*n*/, const double* x, double* /*grad*/, void* data) {
  auto* c = static_cast<SearchContext*>(data);
  const int n = SymmetryVariables(*c->options);
  switch (c->options->objective) {
    case DesignObjective::kAngleCrlb:
      return Evaluate(c, x).metrics.angle_crlb_mrad_per_mm;
    case DesignObjective::kPositionCrlb:
      return Evaluate(c, x).metrics.position_crlb_per_mm;
    case DesignObjective::kRotationOnset:
      return -x[n];
  }
  return 0.0;
}

// COBYLA's linear models break on infinities (a limit that is off is inf): keep values finite.
double Clamped(double v) { return std::clamp(v, -kLargeMm, kLargeMm); }

int NumConstraints(const DesignOptions& o) {
  const int n = o.id_patches, patches = n + 1;
  return n + patches * (patches - 1) / 2 + 1 + (n - 1) * (HasEpigraph(o) ? 2 : 1) + 2;
}

// Every constraint as c(x) <= 0, in mm (or the criterion's unit): rim, pairwise gaps (with
// kSafetyMm to spare), ID capacity, each wrong rotation's onset against the limit (and against
// the epigraph variable), angle and position limits.
void Constraints(unsigned m, double* result, unsigned /*n*/, const double* x, double* /*grad*/,
                 void* data) {
  auto* c = static_cast<SearchContext*>(data);
  const DesignOptions& o = *c->options;
  const LayoutEvaluation& e = Evaluate(c, x);
  const std::vector<Vec2> p = ExpandSymmetry(o, x);
  const double inner = InnerRadius(o) - kSafetyMm;
  unsigned k = 0;
  for (int i = 0; i < o.id_patches; ++i) result[k++] = p[i].norm() + IdRadius(o, i) - inner;
  for (int i = 0; i < o.id_patches; ++i) {
    result[k++] = o.key_radius_mm + IdRadius(o, i) + o.min_gap_mm + kSafetyMm - p[i].norm();
    for (int j = 0; j < i; ++j) {
      result[k++] =
          IdRadius(o, i) + IdRadius(o, j) + o.min_gap_mm + kSafetyMm - (p[i] - p[j]).norm();
    }
  }
  const DesignMetrics& d = e.metrics;
  // Too few IDs: 1 plus how deep the nearest accepted wrong shift lies inside the tolerance.
  result[k++] = d.ids >= RequiredIds(o) ? -1.0 : 1.0 + std::max(0.0, e.accepted_depth_mm);
  for (double onset : e.shift_onset_mm) {
    result[k++] = Clamped(o.min_rotation_onset_mm + kSafetyOnsetMm - onset);
  }
  if (HasEpigraph(o)) {
    for (double onset : e.shift_onset_mm) result[k++] = Clamped(x[SymmetryVariables(o)] - onset);
  }
  result[k++] = Clamped(d.angle_crlb_mrad_per_mm + kSafetyAngle - o.max_angle_crlb_mrad_per_mm);
  result[k++] = Clamped(d.position_crlb_per_mm + kSafetyPosition - o.max_position_crlb_per_mm);
  PATLAB_CHECK(k == m);
}

// A random start: each ID patch at a uniform angle and a uniform radius in the ring where it
// fits, from the stream (seed, "design", start).
std::vector<Vec2> RandomStart(const DesignOptions& o, int start) {
  RandomStream rng(StreamKey(o.seed).Add(std::string_view("design")).value(), kStartStream,
                   static_cast<uint64_t>(start));
  std::vector<Vec2> p(o.id_patches);
  for (int i = 0; i < o.id_patches; ++i) {
    const double r = IdRadius(o, i);
    const double lo = o.key_radius_mm + o.min_gap_mm + r, hi = InnerRadius(o) - r;
    const double phi = rng.Uniform(0.0, 2.0 * std::numbers::pi);
    const double rho = rng.Uniform(lo, hi);
    p[i] = Vec2(rho * std::cos(phi), rho * std::sin(phi));
  }
  return p;
}

// v rounded to 1e-3 mm as the file writes it (3 decimals) and reads it back; never -0.
double RoundedMm(double v) {
  const double r = io::ParseDouble(Mm(v)).value();
  return r == 0.0 ? 0.0 : r;
}

// The layout as written: rotated so that the centroid of all patches lies on the -x axis, ID
// patches sorted by angle (atan2, ascending), positions rounded to 1e-3 mm.
std::vector<Vec2> Canonical(std::vector<Vec2> p) {
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& q : p) centroid += q;
  centroid /= static_cast<double>(p.size() + 1);
  if (centroid.norm() > 1e-6) {
    const double turn = std::numbers::pi - std::atan2(centroid.y(), centroid.x());
    const double c = std::cos(turn), s = std::sin(turn);
    for (Vec2& q : p) q = Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y());
  }
  // Through the text the file holds, so that the layout in memory is the one read back.
  for (Vec2& q : p) q = Vec2(RoundedMm(q.x()), RoundedMm(q.y()));
  std::stable_sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x());
  });
  return p;
}

// One local COBYLA run from `start`; returns the final layout (canonical) in *layout.
DesignStart LocalSearch(const DesignOptions& o, double chi2, int index,
                        const std::vector<Vec2>& start, std::vector<Vec2>* layout) {
  const int n = NumVariables(o), constraints = NumConstraints(o);
  DesignStart s;
  s.start = index;
  SearchContext context;
  context.options = &o;
  context.chi2 = chi2;
  std::vector<double> x = ReduceSymmetry(o, start);
  x.resize(n);
  s.initial = Evaluate(&context, x.data()).metrics;
  const double bound = InnerRadius(o);
  std::vector<double> lower(n, -bound), upper(n, bound), step(n, 0.1 * bound);
  if (HasEpigraph(o)) {  // t from 0 to the clamp, started at the start's onset
    lower[n - 1] = 0.0;
    upper[n - 1] = kLargeMm;
    x[n - 1] = std::clamp(s.initial.rotation_onset_mm, 0.0, kLargeMm);
    step[n - 1] = 0.5;
  }
  nlopt_opt opt = nlopt_create(NLOPT_LN_COBYLA, static_cast<unsigned>(n));
  nlopt_set_lower_bounds(opt, lower.data());
  nlopt_set_upper_bounds(opt, upper.data());
  nlopt_set_min_objective(opt, Objective, &context);
  const std::vector<double> tolerances(constraints, 0.0);
  nlopt_add_inequality_mconstraint(opt, static_cast<unsigned>(constraints), Constraints, &context,
                                   tolerances.data());
  nlopt_set_xtol_abs1(opt, o.xtol_mm);
  nlopt_set_maxeval(opt, o.max_evaluations);
  nlopt_set_initial_step(opt, step.data());
  double value = 0.0;
  nlopt_optimize(opt, x.data(), &value);
  // A second run from where the first ended, with a small first step: COBYLA can end a little
  // outside an active constraint (its merit function trades a violation for the objective at
  // the final trust radius); restarting rebuilds the linear models there and lands on it.
  for (double& h : step) h *= 1e-2;
  nlopt_set_initial_step(opt, step.data());
  s.nlopt_result = static_cast<int>(nlopt_optimize(opt, x.data(), &value));
  nlopt_destroy(opt);
  s.evaluations = context.evaluations;
  *layout = Canonical(ExpandSymmetry(o, x.data()));
  s.final = EvaluateLayout(DesignPattern(o, *layout), o, chi2).metrics;
  return s;
}

double ObjectiveValue(const DesignMetrics& m, DesignObjective objective) {
  switch (objective) {
    case DesignObjective::kAngleCrlb:
      return m.angle_crlb_mrad_per_mm;
    case DesignObjective::kPositionCrlb:
      return m.position_crlb_per_mm;
    case DesignObjective::kRotationOnset:
      return -m.rotation_onset_mm;
  }
  return 0.0;
}

bool FitsGeometry(const DesignMetrics& m, const DesignOptions& o) {
  return m.rim_gap_mm >= o.rim_gap_mm - kGeometryToleranceMm &&
         m.min_gap_mm >= o.min_gap_mm - kGeometryToleranceMm;
}

// The ends of the problem without the limits on onset and CRLBs (IDs and geometry kept) from
// the same starts, judged by the full options: when the limits pull every start of the real
// search out of the robot top, these say what a layout that fits misses.
std::vector<DesignStart> GeometryOnlyEnds(const DesignOptions& o, double chi2) {
  DesignOptions g = o;
  g.min_rotation_onset_mm = 0.0;
  g.max_angle_crlb_mrad_per_mm = g.max_position_crlb_per_mm = kInf;
  std::vector<DesignStart> ends;
  for (int k = 0; k < g.starts; ++k) {
    std::vector<Vec2> layout;
    DesignStart s = LocalSearch(g, chi2, k, RandomStart(g, k), &layout);
    s.final = EvaluateLayout(DesignPattern(o, layout), o, chi2).metrics;
    ends.push_back(std::move(s));
  }
  return ends;
}

// The start that ends inside the robot top with every gap kept and the best objective, or null.
const DesignStart* BestFitting(const std::vector<DesignStart>& starts, const DesignOptions& o) {
  const DesignStart* best = nullptr;
  for (const DesignStart& s : starts) {
    if (!FitsGeometry(s.final, o)) continue;
    if (best == nullptr ||
        ObjectiveValue(s.final, o.objective) < ObjectiveValue(best->final, o.objective)) {
      best = &s;
    }
  }
  return best;
}

[[noreturn]] void ThrowNothingFeasible(const DesignResult& r, double chi2) {
  const DesignOptions& o = r.options;
  const std::vector<DesignStart> geometry_only = GeometryOnlyEnds(o, chi2);
  const DesignStart* best = BestFitting(r.starts, o);
  if (best == nullptr) best = BestFitting(geometry_only, o);
  const std::string searched = " (" + std::to_string(o.starts) + " starts)";
  if (best != nullptr) {
    throw InputError("no layout meets every limit" + searched + "; the best inside the robot " +
                     "top by " + std::string(NameOf(o.objective, kDesignObjectiveNames)) + " has " +
                     best->final.violated);
  }
  throw InputError("no layout of " + std::to_string(o.id_patches) +
                   " ID patches fits with outer_diameter_mm " + FormatNumber(o.outer_diameter_mm) +
                   ", rim_gap_mm " + FormatNumber(o.rim_gap_mm) + ", key_radius_mm " +
                   FormatNumber(o.key_radius_mm) + " and min_gap_mm " + FormatNumber(o.min_gap_mm) +
                   searched +
                   "; expected fewer or smaller ID patches, a smaller min_gap_mm or a larger "
                   "outer_diameter_mm");
}

}  // namespace

DesignResult RunDesign(const DesignOptions& options) {
  Validate(options);
  const auto t0 = std::chrono::steady_clock::now();
  DesignResult r;
  r.options = options;
  std::vector<Vec2> best_layout;
  int best = -1;
  const double chi2 =
      DetectorChiSquared(DesignPattern(options, RandomStart(options, 0)), options.tolerance_mm);
  for (int k = 0; k < options.starts; ++k) {
    const bool given = k == 0 && !options.start_mm.empty();
    std::vector<Vec2> layout;
    DesignStart s =
        LocalSearch(options, chi2, k, given ? options.start_mm : RandomStart(options, k), &layout);
    s.from_options = given;
    r.evaluations += s.evaluations;
    if (s.final.feasible &&
        (best < 0 || ObjectiveValue(s.final, options.objective) <
                         ObjectiveValue(r.starts[best].final, options.objective))) {
      best = k;
      best_layout = layout;
    }
    r.starts.push_back(std::move(s));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.evaluations_per_second = r.seconds > 0 ? static_cast<double>(r.evaluations) / r.seconds : 0;
  if (best < 0) ThrowNothingFeasible(r, chi2);
  r.best_start = best;
  r.pattern = DesignPattern(options, best_layout);
  r.metrics = r.starts[best].final;
  return r;
}

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
  out += "\n" + std::to_string(r.evaluations) + " layouts evaluated\n";
  return out;
}

}  // namespace patlab::sim

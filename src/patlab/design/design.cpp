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
#include "patlab/design/design_internal.h"
#include "patlab/detect/codebook.h"
#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"
#include "patlab/io/csv.h"

namespace patlab::design {

using internal::EvaluateLayout;
using internal::IdRadius;
using internal::InnerRadius;
using internal::kGeometryToleranceMm;
using internal::kInf;
using internal::kLargeMm;
using internal::kSafetyAngle;
using internal::kSafetyMm;
using internal::kSafetyOnsetMm;
using internal::kSafetyPosition;
using internal::kStartStream;
using internal::LayoutEvaluation;
using internal::Mm;
using internal::RequiredIds;

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
    if (options.progress) options.progress(k + 1, options.starts);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.evaluations_per_second = r.seconds > 0 ? static_cast<double>(r.evaluations) / r.seconds : 0;
  if (best < 0) ThrowNothingFeasible(r, chi2);
  r.best_start = best;
  r.pattern = DesignPattern(options, best_layout);
  r.metrics = r.starts[best].final;
  return r;
}

}  // namespace patlab::design

#include "patlab/paper/noise_fit.h"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/pattern.h"
#include "patlab/core/rng.h"
#include "patlab/estimate/bounds.h"
#include "patlab/stats/smoothing.h"

namespace patlab::sim {

std::vector<OptionsProblem> Check(const NoiseFitGeometry& g) {
  OptionsChecker check;
  check
      .Require("id_radius_mm", g.id_radius_mm, g.id_radius_mm > 10.0 && g.id_radius_mm <= 200.0,
               "a number in (10, 200] (mm)")
      .Require("travel_mm", g.travel_mm, g.travel_mm > 0.0 && g.travel_mm <= 10000.0,
               "a number in (0, 10000] (mm)")
      .Require("lateral_mm", g.lateral_mm, g.lateral_mm > 0.0 && g.lateral_mm <= 2000.0,
               "a number in (0, 2000] (mm)")
      .Require("correlation_length_mm", g.correlation_length_mm,
               g.correlation_length_mm > 0.0 && g.correlation_length_mm <= 1e4,
               "a number in (0, 10000] (mm)")
      .Require("smoothing_sigma_samples", g.smoothing_sigma_samples,
               g.smoothing_sigma_samples >= 0.0 && g.smoothing_sigma_samples <= 1000.0,
               "a number in [0, 1000] (samples)");
  return check.Take();
}
void Validate(const NoiseFitGeometry& g) { ThrowFirstProblem(Check(g)); }

std::vector<OptionsProblem> Check(const PaperDataOptions& o) {
  OptionsChecker check;
  check
      .Require("table1_tau", o.table1_tau, o.table1_tau >= 1.0 && o.table1_tau <= 1000.0,
               "a number in [1, 1000]")
      .Require("butterfly_tau", o.butterfly_tau,
               o.butterfly_tau >= 1.0 && o.butterfly_tau <= 1000.0, "a number in [1, 1000]")
      .Require("butterfly_samples", o.butterfly_samples,
               o.butterfly_samples > 5.0 && o.butterfly_samples <= 1e9, "a number in (5, 1e9]")
      .IntegerInRange("butterfly_runs", o.butterfly_runs, 1, 1000);
  return check.Take();
}
void Validate(const PaperDataOptions& o) { ThrowFirstProblem(Check(o)); }

std::vector<OptionsProblem> Check(const NoiseFitOptions& o) {
  OptionsChecker check;
  for (int j = 0; j < kNumMechanisms; ++j) {
    const std::string name(kMechanismNames.entries[static_cast<size_t>(j)].second);
    check.Require("upper." + name, o.upper[j], o.upper[j] > 0.0 && std::isfinite(o.upper[j]),
                  "a finite number > 0");
    check.Require("fixed." + name, o.fixed[j], o.fixed[j] >= 0.0 && o.fixed[j] <= o.upper[j],
                  "a number in [0, upper]");
  }
  check.IntegerInRange("starts", o.starts, 1, 100)
      .IntegerInRange("profile_points", o.profile_points, 3, 1000)
      .IntegerInRange("bootstrap", o.bootstrap, 0, 100000);
  return check.Take();
}
void Validate(const NoiseFitOptions& o) { ThrowFirstProblem(Check(o)); }

std::vector<FitDatum> PaperData(const PaperDataOptions& o) {
  Validate(o);
  // Table I (section II): std and 95% interval per axis; se from the interval's half width.
  struct Row {
    const char* name;
    double s, lo, hi, q;  // q: patlab track, no noise or jitter, est (track_quantisation)
    DatumKind kind;
  };
  const Row rows[] = {{"40mm_x", 0.553, 0.546, 0.561, 0.3485, DatumKind::kPatchX},
                      {"40mm_y", 0.473, 0.467, 0.480, 0.1736, DatumKind::kPatchY},
                      {"50mm_x", 0.543, 0.535, 0.550, 0.3023, DatumKind::kPatchX},
                      {"50mm_y", 0.504, 0.497, 0.511, 0.2252, DatumKind::kPatchY},
                      {"60mm_x", 0.489, 0.482, 0.496, 0.1943, DatumKind::kPatchX},
                      {"60mm_y", 0.533, 0.526, 0.541, 0.1798, DatumKind::kPatchY}};
  std::vector<FitDatum> data;
  for (const Row& r : rows) {
    const double se = (r.hi - r.lo) / (2.0 * 1.959964) * std::sqrt(o.table1_tau);
    data.push_back({r.name, r.kind, r.s, se, r.q, true});
  }
  // Section IV: no intervals printed; chi-square se s / sqrt(2 dof), dof = n - runs, over tau.
  const double dof = (o.butterfly_samples - o.butterfly_runs) / o.butterfly_tau;
  const auto se = [&](double s) { return s / std::sqrt(2.0 * dof); };
  data.push_back({"butterfly_x", DatumKind::kPatternX, 0.3766, se(0.3766), 0.0985, false});
  data.push_back({"butterfly_y", DatumKind::kPatternY, 0.3432, se(0.3432), 0.0940, false});
  data.push_back(
      {"butterfly_theta", DatumKind::kPatternTheta, 0.0070, se(0.0070), 0.001797, false});
  return data;
}

estimate::Model ButterflyModel(double id_radius_mm) {
  // patterns/butterfly.toml: ID dots at +-57.4 and +-147.4 degrees on a 65 mm circle.
  const double a = 57.4 * std::numbers::pi / 180.0, b = 147.4 * std::numbers::pi / 180.0;
  Pattern p;
  p.name = "butterfly";
  Patch key;
  key.radius_mm = 25.0;
  key.role = PatchRole::kKey;
  p.patches.push_back(key);
  for (double angle : {a, -a, b, -b}) {
    Patch dot;
    dot.position_mm = id_radius_mm * Vec2(std::cos(angle), std::sin(angle));
    dot.radius_mm = 20.0;
    dot.role = PatchRole::kId;
    p.patches.push_back(dot);
  }
  p.orientation_pairs = DefaultOrientationPairs(p.patches, 0);
  return estimate::Model::FromPattern(p);
}

namespace {

// A dense row-major square matrix (plain loops: the sizes are <= 2 kMaxPatches).
struct Square {
  int n = 0;
  std::vector<double> v;
  explicit Square(int size) : n(size), v(static_cast<size_t>(size * size), 0.0) {}
  double& operator()(int r, int c) { return v[static_cast<size_t>(r * n + c)]; }
  double operator()(int r, int c) const { return v[static_cast<size_t>(r * n + c)]; }
};

// Heading-averaged pose variances (x, y, theta) of the fast estimator for world-frame patch error
// covariance D (2n x 2n): J(psi) = diag(R(psi), 1) G diag_i(R(-psi)), 64 headings (exact for
// these trigonometric polynomials of degree <= 4).
std::array<double, 3> PoseVariance(const estimate::Model& model, const Square& d) {
  const int n = model.num_patches;
  const estimate::PoseJacobian g = estimate::EstimatorJacobian(model, estimate::Estimator::kFast);
  std::array<double, 3> sum{};
  constexpr int kHeadings = 64;
  std::vector<std::array<double, 3>> j(static_cast<size_t>(2 * n));  // columns of J
  for (int h = 0; h < kHeadings; ++h) {
    const double psi = 2.0 * std::numbers::pi * h / kHeadings;
    const double c = std::cos(psi), s = std::sin(psi);
    for (int i = 0; i < n; ++i) {
      // d' = R(-psi) d: d'_x = c d_x + s d_y, d'_y = -s d_x + c d_y.
      for (int axis = 0; axis < 2; ++axis) {
        const double to_x = axis == 0 ? c : s, to_y = axis == 0 ? -s : c;
        std::array<double, 3> col{};
        for (int r = 0; r < 3; ++r) col[r] = g(r, 2 * i) * to_x + g(r, 2 * i + 1) * to_y;
        j[static_cast<size_t>(2 * i + axis)] = {c * col[0] - s * col[1], s * col[0] + c * col[1],
                                                col[2]};
      }
    }
    for (int r = 0; r < 3; ++r) {
      for (int a = 0; a < 2 * n; ++a) {
        for (int b = 0; b < 2 * n; ++b) {
          sum[r] += j[static_cast<size_t>(a)][r] * d(a, b) * j[static_cast<size_t>(b)][r];
        }
      }
    }
  }
  for (double& v : sum) v /= kHeadings;
  return sum;
}

// Per-patch covariance of each per-patch mechanism on the Butterfly (unit magnitude).
Square PatchCovariance(const estimate::Model& model, Mechanism m, double length_mm) {
  const int n = model.num_patches;
  Square d(2 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double dist = (model.model_mm[i] - model.model_mm[j]).norm();
      for (int axis = 0; axis < 2; ++axis) {
        double v = 0.0;
        if (m == Mechanism::kCorrelated) v = std::exp(-dist / length_mm);
        if (i == j && (m == Mechanism::kColour || (m == Mechanism::kIndependentX && axis == 0) ||
                       (m == Mechanism::kIndependentY && axis == 1))) {
          v = 1.0;
        }
        d(2 * i + axis, 2 * j + axis) = v;
      }
    }
  }
  return d;
}

// Lower Cholesky factor of exp(-|p_i - p_j| / length) (positive definite for distinct points).
Square CorrelationFactor(const estimate::Model& model, double length_mm) {
  const int n = model.num_patches;
  Square l(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      double sum = std::exp(-(model.model_mm[i] - model.model_mm[j]).norm() / length_mm);
      for (int k = 0; k < j; ++k) sum -= l(i, k) * l(j, k);
      l(i, j) = i == j ? std::sqrt(sum) : sum / l(j, j);
    }
  }
  return l;
}

}  // namespace

FitDesign BuildDesign(const std::vector<FitDatum>& data, const NoiseFitGeometry& geometry) {
  Validate(geometry);
  FitDesign design;
  design.data = data;
  design.k = geometry.smoothing_sigma_samples > 0.0
                 ? stats::ResidualStdFactor({geometry.smoothing_sigma_samples, 4.0})
                 : 1.0;
  const double ex = geometry.travel_mm * geometry.travel_mm / 12.0;
  const double ey = geometry.lateral_mm * geometry.lateral_mm / 12.0;
  const estimate::Model model = ButterflyModel(geometry.id_radius_mm);
  std::array<std::array<double, 3>, kNumMechanisms> pattern{};
  for (Mechanism m : {Mechanism::kIndependentX, Mechanism::kIndependentY, Mechanism::kCorrelated,
                      Mechanism::kColour}) {
    pattern[static_cast<size_t>(m)] =
        PoseVariance(model, PatchCovariance(model, m, geometry.correlation_length_mm));
  }
  const double pbar2 = model.centroid_mm.squaredNorm() / 2.0;
  pattern[static_cast<size_t>(Mechanism::kCommon)] = {1.0, 1.0, 0.0};
  pattern[static_cast<size_t>(Mechanism::kRoll)] = {1e-6 * ey, 1e-6 * ex, 1e-6};
  pattern[static_cast<size_t>(Mechanism::kScale)] = {1e-12 * (ex + pbar2), 1e-12 * (ey + pbar2),
                                                     0.0};
  for (const FitDatum& datum : data) {
    Magnitudes a{};
    switch (datum.kind) {
      case DatumKind::kPatchX:
        a = {1.0, 0.0, 1.0, 1e-6 * ey, 1e-12 * ex, 1.0, 0.0};
        break;
      case DatumKind::kPatchY:
        a = {0.0, 1.0, 1.0, 1e-6 * ex, 1e-12 * ey, 1.0, 0.0};
        break;
      default: {
        const int axis = datum.kind == DatumKind::kPatternX   ? 0
                         : datum.kind == DatumKind::kPatternY ? 1
                                                              : 2;
        for (int j = 0; j < kNumMechanisms; ++j) a[j] = pattern[static_cast<size_t>(j)][axis];
      }
    }
    design.coefficient.push_back(a);
    design.base.push_back(datum.quantisation * datum.quantisation);
  }
  return design;
}

std::vector<double> Predict(const FitDesign& design, const Magnitudes& m) {
  std::vector<double> out(design.data.size());
  for (size_t i = 0; i < out.size(); ++i) {
    double v = 0.0;
    for (int j = 0; j < kNumMechanisms; ++j) v += design.coefficient[i][j] * m[j] * m[j];
    out[i] = std::sqrt(design.base[i] + design.k * design.k * v);
  }
  return out;
}

namespace {

// The fit's state: which magnitudes are free, the data (the real or a bootstrap replicate) and
// an optionally profiled magnitude held at a value.
struct Problem {
  const FitDesign* design = nullptr;
  std::vector<double> observed;
  std::vector<int> free;  // mechanism indices fitted
  Magnitudes held{};      // values of the others
  bool fit_delta = true;
  double delta_upper = 0.5;
  long evaluations = 0;

  int Size() const { return static_cast<int>(free.size()) + (fit_delta ? 1 : 0); }
  Magnitudes Unpack(const double* x, double* delta) const {
    Magnitudes m = held;
    for (size_t k = 0; k < free.size(); ++k) m[free[k]] = x[k];
    *delta = fit_delta ? x[free.size()] : 0.0;
    return m;
  }
  double Minus2LogL(const Magnitudes& m, double delta) const {
    const std::vector<double> pred = Predict(*design, m);
    double f = 0.0;
    for (size_t i = 0; i < pred.size(); ++i) {
      const FitDatum& d = design->data[i];
      const double s2 = d.se * d.se + (d.table1 ? delta * delta : 0.0);
      const double r = observed[i] - pred[i];
      f += r * r / s2 + std::log(s2);
    }
    return f;
  }
};

double Objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  (void)n;
  auto* p = static_cast<Problem*>(data);
  ++p->evaluations;
  double delta = 0.0;
  const Magnitudes m = p->Unpack(x, &delta);
  return p->Minus2LogL(m, delta);
}

struct Minimum {
  std::vector<double> x;
  double value = 0.0;
};

Minimum Polish(Problem* p, const std::vector<double>& lower, const std::vector<double>& upper,
               std::vector<double> x) {
  const unsigned n = static_cast<unsigned>(x.size());
  Minimum out;
  if (n == 0) {
    out.value = Objective(0, nullptr, nullptr, p);
    return out;
  }
  nlopt_opt opt = nlopt_create(n >= 2 ? NLOPT_LN_BOBYQA : NLOPT_LN_COBYLA, n);
  nlopt_set_lower_bounds(opt, lower.data());
  nlopt_set_upper_bounds(opt, upper.data());
  nlopt_set_min_objective(opt, Objective, p);
  nlopt_set_xtol_rel(opt, 1e-9);
  nlopt_set_ftol_abs(opt, 1e-10);
  nlopt_set_maxeval(opt, 20000);
  double value = 0.0;
  for (int pass = 0; pass < 2; ++pass) {  // a restart escapes BOBYQA's early stalls
    std::vector<double> step(n);
    for (unsigned k = 0; k < n; ++k) step[k] = 0.1 * (upper[k] - lower[k]);
    nlopt_set_initial_step(opt, step.data());
    nlopt_optimize(opt, x.data(), &value);
  }
  nlopt_destroy(opt);
  out.x = x;
  out.value = value;
  return out;
}

// The minimum over the free magnitudes (and delta) from `starts` deterministic points plus
// `hint` (when its size fits).
Minimum Minimise(Problem* p, const NoiseFitOptions& o, int starts, uint64_t stream_index,
                 const std::vector<double>& hint) {
  const int n = p->Size();
  std::vector<double> lower(static_cast<size_t>(n), 0.0), upper(static_cast<size_t>(n));
  for (size_t k = 0; k < p->free.size(); ++k) upper[k] = o.upper[p->free[k]];
  if (p->fit_delta) upper[p->free.size()] = p->delta_upper;
  Minimum best;
  best.value = INFINITY;
  RandomStream rng(o.seed, 0x6e666974 /* "nfit" */, stream_index);
  for (int s = 0; s <= starts; ++s) {
    std::vector<double> x(static_cast<size_t>(n));
    if (s == 0 && static_cast<int>(hint.size()) == n) {
      x = hint;
    } else {
      for (int k = 0; k < n; ++k) x[k] = rng.Uniform(0.05, 0.7) * upper[k];
    }
    const Minimum m = Polish(p, lower, upper, x);
    if (m.value < best.value) best = m;
  }
  return best;
}

Problem MakeProblem(const FitDesign& design, const NoiseFitOptions& o,
                    const std::vector<double>& observed) {
  Problem p;
  p.design = &design;
  p.observed = observed;
  p.held = o.fixed;
  p.fit_delta = o.fit_delta;
  for (int j = 0; j < kNumMechanisms; ++j)
    if (o.free[j]) p.free.push_back(j);
  return p;
}

// The profile of magnitude j: minimum of -2 log L with m_j held at `value`.
double ProfileAt(const FitDesign& design, const NoiseFitOptions& o, int j, double value,
                 std::vector<double>* hint, uint64_t stream) {
  std::vector<double> observed;
  for (const FitDatum& d : design.data) observed.push_back(d.observed);
  Problem p = MakeProblem(design, o, observed);
  p.free.erase(std::find(p.free.begin(), p.free.end(), j));
  p.held[j] = value;
  const Minimum m = Minimise(&p, o, 2, stream, *hint);
  *hint = m.x;
  return m.value;
}

constexpr double kLevel95 = 3.841459;  // chi2_1 quantile 0.95

// The crossing of the 95% level between a (profile below) and b (above), by bisection.
double Crossing(const FitDesign& design, const NoiseFitOptions& o, int j, double a, double b,
                double minimum, std::vector<double> hint) {
  for (int it = 0; it < 30 && std::abs(b - a) > 1e-6 * o.upper[j]; ++it) {
    const double mid = 0.5 * (a + b);
    const double v = ProfileAt(design, o, j, mid, &hint, 1000 + j) - minimum;
    (v < kLevel95 ? a : b) = mid;
  }
  return 0.5 * (a + b);
}

// From the estimate towards `end` (0 or the search bound): steps doubling from 1% of the bound
// until the profile passes the level, then bisection. Returns `end` when it never does.
double Walk(const FitDesign& design, const NoiseFitOptions& o, int j, double start, double end,
            double minimum, const std::vector<double>& best_hint, bool* crossed) {
  std::vector<double> hint = best_hint;
  const double dir = end > start ? 1.0 : -1.0;
  double a = start, h = 0.01 * o.upper[j];
  *crossed = false;
  while (dir * (end - a) > 0.0) {
    const double b = dir > 0 ? std::min(end, a + h) : std::max(end, a - h);
    std::vector<double> at_b = hint;
    if (ProfileAt(design, o, j, b, &at_b, 100 + j) - minimum >= kLevel95) {
      *crossed = true;
      return Crossing(design, o, j, a, b, minimum, hint);
    }
    a = b;
    hint = at_b;
    h *= 2.0;
  }
  return end;
}

void ProfileInterval(const FitDesign& design, const NoiseFitOptions& o, const NoiseFitResult& r,
                     const std::vector<double>& best_x, MechanismEstimate* e) {
  const int j = static_cast<int>(e->mechanism);
  // The global minimum's other coordinates as the first hint.
  std::vector<double> hint;
  int k = 0;
  for (int m = 0; m < kNumMechanisms; ++m) {
    if (!o.free[m]) continue;
    if (m != j) hint.push_back(best_x[static_cast<size_t>(k)]);
    ++k;
  }
  if (o.fit_delta) hint.push_back(best_x.back());
  bool crossed_low = false, crossed_high = false;
  e->lower = Walk(design, o, j, e->value, 0.0, r.minus2_log_l, hint, &crossed_low);
  e->upper = Walk(design, o, j, e->value, o.upper[j], r.minus2_log_l, hint, &crossed_high);
  e->verdict = !crossed_high  ? Identifiability::kUnidentified
               : !crossed_low ? Identifiability::kUpperBound
                              : Identifiability::kIdentified;
  if (!crossed_low) e->lower = 0.0;
  // The curve for the figures: a window twice the interval's width around it.
  const double width = std::max(e->upper - e->lower, 1e-3 * o.upper[j]);
  const double lo = std::max(0.0, e->lower - 0.5 * width);
  const double hi = std::min(o.upper[j], e->upper + 0.5 * width);
  std::vector<double> h = hint;
  for (int p = 0; p < o.profile_points; ++p) {
    const double value = lo + (hi - lo) * p / (o.profile_points - 1);
    const double v = ProfileAt(design, o, j, value, &h, 100 + j) - r.minus2_log_l;
    e->profile.push_back({value, std::max(0.0, v)});
  }
}

void Bootstrap(const FitDesign& design, const NoiseFitOptions& o, NoiseFitResult* r,
               const std::vector<double>& best_x) {
  const int nf = kNumMechanisms;
  r->correlation.assign(static_cast<size_t>(nf * nf), std::nan(""));
  if (o.bootstrap < 2) return;
  std::vector<Magnitudes> draws;
  for (int b = 0; b < o.bootstrap; ++b) {
    RandomStream rng(o.seed, 0x6e626f74 /* "nbot" */, static_cast<uint64_t>(b));
    std::vector<double> obs(design.data.size());
    for (size_t i = 0; i < obs.size(); ++i) {
      const FitDatum& d = design.data[i];
      const double s = std::sqrt(d.se * d.se + (d.table1 ? r->delta * r->delta : 0.0));
      obs[i] = r->predicted[i] + s * rng.Normal();
    }
    Problem p = MakeProblem(design, o, obs);
    const Minimum m = Minimise(&p, o, 2, 10000 + static_cast<uint64_t>(b), best_x);
    double delta = 0.0;
    draws.push_back(p.Unpack(m.x.data(), &delta));
  }
  const double n = static_cast<double>(draws.size());
  Magnitudes mean{}, sd{};
  for (const Magnitudes& d : draws)
    for (int j = 0; j < nf; ++j) mean[j] += d[j] / n;
  for (const Magnitudes& d : draws)
    for (int j = 0; j < nf; ++j) sd[j] += (d[j] - mean[j]) * (d[j] - mean[j]);
  for (int a = 0; a < nf; ++a) {
    for (int b = 0; b < nf; ++b) {
      if (!o.free[a] || !o.free[b] || sd[a] <= 0.0 || sd[b] <= 0.0) continue;
      double c = 0.0;
      for (const Magnitudes& d : draws) c += (d[a] - mean[a]) * (d[b] - mean[b]);
      r->correlation[static_cast<size_t>(a * nf + b)] = c / std::sqrt(sd[a] * sd[b]);
    }
  }
  for (MechanismEstimate& e : r->estimates) {
    const int j = static_cast<int>(e.mechanism);
    std::vector<double> v;
    for (const Magnitudes& d : draws) v.push_back(d[j]);
    std::sort(v.begin(), v.end());
    e.boot_lower = v[static_cast<size_t>(0.025 * (n - 1))];
    e.boot_upper = v[static_cast<size_t>(std::ceil(0.975 * (n - 1)))];
    for (int b = 0; b < nf; ++b) {
      const double c = r->correlation[static_cast<size_t>(j * nf + b)];
      if (b != j && std::isfinite(c) && std::abs(c) > std::abs(e.correlation)) {
        e.correlation = c;
        e.most_correlated = b;
      }
    }
  }
}

}  // namespace

NoiseFitResult FitNoise(const FitDesign& design, const NoiseFitOptions& o) {
  Validate(o);
  std::vector<double> observed;
  for (const FitDatum& d : design.data) {
    if (!(d.se > 0.0))
      throw InputError("noise fit: datum " + d.name + " has se <= 0; expected > 0");
    observed.push_back(d.observed);
  }
  Problem p = MakeProblem(design, o, observed);
  const Minimum m = Minimise(&p, o, o.starts, 0, {});
  NoiseFitResult r;
  r.best = p.Unpack(m.x.data(), &r.delta);
  r.minus2_log_l = m.value;
  r.free_parameters = p.Size();
  r.predicted = Predict(design, r.best);
  for (size_t i = 0; i < design.data.size(); ++i) {
    const FitDatum& d = design.data[i];
    const double s2 = d.se * d.se + (d.table1 ? r.delta * r.delta : 0.0);
    r.chi2 += (d.observed - r.predicted[i]) * (d.observed - r.predicted[i]) / s2;
  }
  for (int j = 0; j < kNumMechanisms; ++j) {
    MechanismEstimate e;
    e.mechanism = static_cast<Mechanism>(j);
    e.free = o.free[j];
    e.value = e.lower = e.upper = r.best[j];
    if (e.free) ProfileInterval(design, o, r, m.x, &e);
    r.estimates.push_back(std::move(e));
  }
  Bootstrap(design, o, &r, m.x);
  return r;
}

FitDesign AddTable1Discrepancy(const FitDesign& design, double* delta_mm) {
  FitDesign table1;
  table1.k = design.k;
  for (size_t i = 0; i < design.data.size(); ++i) {
    if (!design.data[i].table1) continue;
    table1.data.push_back(design.data[i]);
    table1.coefficient.push_back(design.coefficient[i]);
    table1.base.push_back(design.base[i]);
  }
  NoiseFitOptions o;
  o.free[static_cast<size_t>(Mechanism::kIndependentX)] = true;
  o.free[static_cast<size_t>(Mechanism::kIndependentY)] = true;
  o.fit_delta = true;
  o.profile_points = 3;
  o.bootstrap = 0;
  *delta_mm = table1.data.empty() ? 0.0 : FitNoise(table1, o).delta;
  FitDesign out = design;
  for (FitDatum& d : out.data)
    if (d.table1) d.se = std::hypot(d.se, *delta_mm);
  return out;
}

namespace {

// Adds one run's squared error estimates to `sum2` and their degrees of freedom to `count`: the
// residuals of the paper's Gaussian smoothing, or, without smoothing, the deviations from the
// run's mean (one degree of freedom spent on it).
void AddRunResiduals(const std::vector<double>& run, const stats::SmoothingOptions& smoothing,
                     double& sum2, double& count) {
  std::vector<double> resid;
  if (smoothing.sigma_samples > 0.0) {
    resid = stats::SmoothingResiduals(run, smoothing);
  } else {
    const double frames = static_cast<double>(run.size());
    double mean = 0.0;
    for (double v : run) mean += v / frames;
    for (double v : run) resid.push_back(v - mean);
  }
  for (double v : resid) sum2 += v * v;
  count += static_cast<double>(run.size()) - (smoothing.sigma_samples > 0.0 ? 0.0 : 1.0);
}

}  // namespace

std::vector<double> SimulateTrack(const std::vector<FitDatum>& data,
                                  const NoiseFitGeometry& geometry, const Magnitudes& m, int runs,
                                  int frames, uint64_t seed) {
  Validate(geometry);
  if (runs < 1 || frames < 30) {
    throw InputError("noise fit track: runs " + std::to_string(runs) + ", frames " +
                     std::to_string(frames) + "; expected runs >= 1 and frames >= 30");
  }
  const estimate::Model model = ButterflyModel(geometry.id_radius_mm);
  const int n = model.num_patches;
  const Square chol = CorrelationFactor(model, geometry.correlation_length_mm);
  // Series: patch x, patch y, pattern x, y, theta.
  std::array<double, 5> sum2{};
  std::array<double, 5> count{};
  const stats::SmoothingOptions smoothing{geometry.smoothing_sigma_samples, 4.0};
  std::array<std::vector<double>, 5> series;
  for (int r = 0; r < runs; ++r) {
    RandomStream path(seed, 0x6e747270 /* "ntrp" */, static_cast<uint64_t>(r));
    const double offset = path.Uniform(-0.5, 0.5) * geometry.lateral_mm;
    const double heading = path.Uniform(-std::numbers::pi, std::numbers::pi);
    for (auto& s : series) s.assign(static_cast<size_t>(frames), 0.0);
    for (int f = 0; f < frames; ++f) {
      RandomStream rng(seed, 0x6e74666d /* "ntfm" */,
                       static_cast<uint64_t>(r) * static_cast<uint64_t>(frames) + f);
      const Vec2 t(geometry.travel_mm * (static_cast<double>(f) / (frames - 1) - 0.5), offset);
      const Vec2 common = m[2] * Vec2(rng.Normal(), rng.Normal());
      const double phi = 1e-3 * m[3] * rng.Normal(), eps = 1e-6 * m[4] * rng.Normal();
      const double cs = (1.0 + eps) * std::cos(phi), sn = (1.0 + eps) * std::sin(phi);
      const auto camera = [&](const Vec2& v) {
        return Vec2(cs * v.x() - sn * v.y(), sn * v.x() + cs * v.y());
      };
      // The single white patch at t: independent, correlated (its own variance) and common.
      const Vec2 patch = t + Vec2(m[0] * rng.Normal(), m[1] * rng.Normal()) +
                         m[5] * Vec2(rng.Normal(), rng.Normal()) + common;
      const Vec2 patch_error = camera(patch) - t;
      series[0][f] = patch_error.x();
      series[1][f] = patch_error.y();
      // The Butterfly at (t, heading).
      std::array<double, kMaxPatches> zx{}, zy{}, cx{}, cy{};
      for (int i = 0; i < n; ++i) zx[i] = rng.Normal(), zy[i] = rng.Normal();
      for (int i = 0; i < n; ++i)
        for (int k = 0; k <= i; ++k) cx[i] += chol(i, k) * zx[k], cy[i] += chol(i, k) * zy[k];
      const Pose2 truth{t.x(), t.y(), heading};
      std::array<Vec2, kMaxPatches> observed{};
      for (int i = 0; i < n; ++i) {
        const Vec2 e = Vec2(m[0] * rng.Normal(), m[1] * rng.Normal()) + m[5] * Vec2(cx[i], cy[i]) +
                       m[6] * Vec2(rng.Normal(), rng.Normal()) + common;
        observed[static_cast<size_t>(i)] = camera(truth.Apply(model.model_mm[i]) + e);
      }
      const Pose2 est = estimate::Fast(model, observed.data());
      series[2][f] = est.x_mm - t.x();
      series[3][f] = est.y_mm - t.y();
      series[4][f] = WrapAngle(est.theta_rad - heading);
    }
    for (size_t s = 0; s < series.size(); ++s)
      AddRunResiduals(series[s], smoothing, sum2[s], count[s]);
  }
  std::vector<double> out;
  for (const FitDatum& d : data) {
    const size_t s = static_cast<size_t>(d.kind);
    out.push_back(std::sqrt(d.quantisation * d.quantisation + sum2[s] / count[s]));
  }
  return out;
}

}  // namespace patlab::sim

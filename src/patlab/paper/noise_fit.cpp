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

namespace patlab::paper {

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
               const std::vector<double>& best_x, const std::function<void()>& step) {
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
    if (step) step();
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

NoiseFitResult FitNoise(const FitDesign& design, const NoiseFitOptions& o,
                        const std::function<void()>& step) {
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
  if (step) step();
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
    if (e.free) {
      ProfileInterval(design, o, r, m.x, &e);
      if (step) step();
    }
    r.estimates.push_back(std::move(e));
  }
  Bootstrap(design, o, &r, m.x, step);
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

}  // namespace patlab::paper

// The noise fit's model (noise_fit.h): the paper's data, the Butterfly's pose variances under
// each per-patch mechanism (the design of the fit), its predictions, and the simulated tracks of
// the fitted model.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/pattern.h"
#include "patlab/core/rng.h"
#include "patlab/estimate/bounds.h"
#include "patlab/paper/noise_fit.h"
#include "patlab/stats/smoothing.h"

namespace patlab::paper {

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

// Two standard normals as (x, y), y drawn first.
Vec2 NormalPair(RandomStream& rng) {
  const double y = rng.Normal();
  const double x = rng.Normal();
  return {x, y};
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
      // The draws are sequenced one by one (NormalPair): C++ leaves the order of a call's
      // arguments and of an expression's operands unspecified, and a compiler's choice must not
      // change the results. The order is the one GCC took when this was written in one expression
      // (its committed numbers): the last term's pair first, each pair's y before its x.
      const Vec2 common = m[2] * NormalPair(rng);
      const double phi = 1e-3 * m[3] * rng.Normal(), eps = 1e-6 * m[4] * rng.Normal();
      const double cs = (1.0 + eps) * std::cos(phi), sn = (1.0 + eps) * std::sin(phi);
      const auto camera = [&](const Vec2& v) {
        return Vec2(cs * v.x() - sn * v.y(), sn * v.x() + cs * v.y());
      };
      // The single white patch at t: independent, correlated (its own variance) and common.
      const Vec2 patch_correlated = NormalPair(rng);
      const Vec2 patch_own = NormalPair(rng);
      const Vec2 patch =
          t + Vec2(m[0] * patch_own.x(), m[1] * patch_own.y()) + m[5] * patch_correlated + common;
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
        const Vec2 jitter = NormalPair(rng);
        const Vec2 own = NormalPair(rng);
        const Vec2 e = Vec2(m[0] * own.x(), m[1] * own.y()) + m[5] * Vec2(cx[i], cy[i]) +
                       m[6] * jitter + common;
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

}  // namespace patlab::paper

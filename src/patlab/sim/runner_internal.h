// Pieces of the known-correspondence runner shared by runner.cpp (points, blocks and the run)
// and runner_statistics.cpp (a block's moments, KS and Wilcoxon comparisons). Not part of the
// public API: include runner.h instead.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "patlab/estimate/estimators.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/runner.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::sim::internal {

// Per-estimator sample arrays of one point.
struct Samples {
  std::vector<double> x, y, theta;
  void Resize(int64_t n) {
    x.resize(n);
    y.resize(n);
    theta.resize(n);
  }
};

// The block's moments of every estimator: x, y, theta and the radial error sqrt(x^2 + y^2) (not
// stored: computed a tile at a time in each pass), all in one stats::PlanarMomentsOfEach call, so
// that the estimators' addition chains overlap in one loop; the arithmetic is that of Mean and
// SampleStd, every sum in index order. With `visit`, each tile of the second pass is shown to it
// (PlanarMomentsOfEach's overload; samples in the order of experiment.estimators).
void BlockMoments(const Experiment& experiment, const Samples* by_estimator, size_t size,
                  std::span<EstimatorBlock> out,
                  const std::function<void(const stats::PlanarTile&)>* visit = nullptr);

// Two blocks' statistics folded, a before b (trial order).
EstimatorBlock Fold(const EstimatorBlock& a, const EstimatorBlock& b);

// The paired Wilcoxon signed-rank tests compare |error| of fast and of another estimator trial by
// trial. A difference below 1e-10 (mm or rad) + 1e-12 relative is rounding (fast, ml and lsq are
// the same estimator on Simple, Linear and Triangle, and the errors carry the ~1e-13 rounding of
// poses of ~1e3 mm) and counts as a zero, which the 'wilcox' zero method drops.
inline double PairedDifference(double a, double b) {
  const double diff = a - b;
  const bool rounding = std::abs(diff) <= 1e-10 + 1e-12 * std::max(std::abs(a), std::abs(b));
  return rounding ? 0.0 : diff;
}

// The test of the differences d, `nonzero` of them not zero, ranked in place (d overwritten) with
// `scratch` (an array of at least d.size() elements whose contents are dead): no memory that grows
// with the trials. If every difference is a zero, the samples carry no evidence of a difference:
// p = 1.
stats::WilcoxonResult PairedTest(std::span<double> d, size_t nonzero, std::span<double> scratch);

// The comparisons of the first block with fast, in three steps that share the moments' pass over
// the samples:
// 1. the KS tests of each compared estimator's x, y and theta against fast's (they only read);
// 2. the moments (BlockMoments), whose second pass shows each tile's radial errors to Differences:
//    it writes the paired differences of |position error| over the compared estimator's x and of
//    |theta error| over its theta, tile by tile once the moments have read them, so that the
//    paired tests need no pass and no square root of their own;
// 3. the two Wilcoxon tests of each, ranked in place with the estimator's y (dead once the
//    differences are written) as the scratch.
// fast's arrays are only read; no array of the trials' size is needed beyond the samples
// (docs/hardening.md, "Bounded memory").
void KsAgainstFast(const Samples& fast, const Samples& other, size_t n, Comparison* c);

// Step 2's visitor state: the compared estimators' sample indices (in experiment.estimators) and
// arrays, fast's, and the count of differences that are not zero, per estimator.
struct Differences {
  size_t fast_index = 0;
  const Samples* fast = nullptr;
  std::array<Samples*, estimate::kNumEstimators> other{};  // by sample index; null for fast
  std::array<size_t, estimate::kNumEstimators> nonzero_position{}, nonzero_theta{};

  void operator()(const stats::PlanarTile& tile) {
    const double* rf = tile.radial[fast_index];
    const double* tf = fast->theta.data() + tile.first;
    for (size_t k = 0; k < other.size(); ++k) {
      if (other[k] == nullptr) continue;
      const double* ro = tile.radial[k];
      double* dp = other[k]->x.data() + tile.first;
      double* dt = other[k]->theta.data() + tile.first;
      size_t np = 0, nt = 0;
      for (size_t j = 0; j < tile.count; ++j) {
        dp[j] = PairedDifference(rf[j], ro[j]);
        np += dp[j] != 0.0 ? 1 : 0;
      }
      for (size_t j = 0; j < tile.count; ++j) {
        dt[j] = PairedDifference(std::abs(tf[j]), std::abs(dt[j]));
        nt += dt[j] != 0.0 ? 1 : 0;
      }
      nonzero_position[k] += np;
      nonzero_theta[k] += nt;
    }
  }
};

}  // namespace patlab::sim::internal

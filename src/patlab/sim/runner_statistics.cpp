// A block's statistics for the known-correspondence runner (runner_internal.h): the estimators'
// moments in one pass, the blocks folded in trial order, and the KS and paired Wilcoxon
// comparisons with fast.
#include <tbb/parallel_invoke.h>

#include <array>
#include <functional>
#include <span>

#include "patlab/sim/runner_internal.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::sim::internal {

void BlockMoments(const Experiment& experiment, const Samples* by_estimator, size_t size,
                  std::span<EstimatorBlock> out,
                  const std::function<void(const stats::PlanarTile&)>* visit) {
  std::array<stats::PlanarSample, estimate::kNumEstimators> samples;
  std::array<stats::PlanarMoments, estimate::kNumEstimators> moments;
  const size_t count = experiment.estimators.size();
  PATLAB_CHECK(count <= samples.size());
  for (size_t k = 0; k < count; ++k) {
    const Samples& s = by_estimator[static_cast<int>(experiment.estimators[k])];
    samples[k] = stats::PlanarSample{std::span<const double>(s.x.data(), size),
                                     std::span<const double>(s.y.data(), size),
                                     std::span<const double>(s.theta.data(), size)};
  }
  if (visit != nullptr) {
    stats::PlanarMomentsOfEach(std::span(samples).first(count), std::span(moments).first(count),
                               *visit);
  } else {
    stats::PlanarMomentsOfEach(std::span(samples).first(count), std::span(moments).first(count));
  }
  for (size_t k = 0; k < count; ++k) {
    out[k].x = moments[k].x;
    out[k].y = moments[k].y;
    out[k].theta = moments[k].theta;
    out[k].radial = moments[k].radial;
    out[k].sum_sq = moments[k].sum_sq;
  }
}

EstimatorBlock Fold(const EstimatorBlock& a, const EstimatorBlock& b) {
  EstimatorBlock f;
  f.x = stats::CombineMoments(a.x, b.x);
  f.y = stats::CombineMoments(a.y, b.y);
  f.theta = stats::CombineMoments(a.theta, b.theta);
  f.radial = stats::CombineMoments(a.radial, b.radial);
  f.sum_sq = a.sum_sq + b.sum_sq;
  f.iterations = a.iterations + b.iterations;
  f.nonconverged = a.nonconverged + b.nonconverged;
  f.first_nonconverged_trial =
      a.first_nonconverged_trial >= 0 ? a.first_nonconverged_trial : b.first_nonconverged_trial;
  f.vs_fast = a.x.n == 0 ? b.vs_fast : a.vs_fast;
  return f;
}

stats::WilcoxonResult PairedTest(std::span<double> d, size_t nonzero, std::span<double> scratch) {
  if (nonzero == 0) {
    stats::WilcoxonResult identical;
    identical.n = identical.n_zero = d.size();
    identical.p_value = 1.0;
    return identical;
  }
  return stats::WilcoxonSignedRankInPlace(d, scratch);
}

void KsAgainstFast(const Samples& fast, const Samples& other, size_t n, Comparison* c) {
  c->computed = true;
  c->trials = static_cast<int64_t>(n);
  const auto head = [n](const std::vector<double>& v) {
    return std::span<const double>(v.data(), n);
  };
  tbb::parallel_invoke(
      [&] { c->ks_x = stats::KsTwoSample(head(fast.x), head(other.x)); },
      [&] { c->ks_y = stats::KsTwoSample(head(fast.y), head(other.y)); },
      [&] { c->ks_theta = stats::KsTwoSample(head(fast.theta), head(other.theta)); });
}

}  // namespace patlab::sim::internal

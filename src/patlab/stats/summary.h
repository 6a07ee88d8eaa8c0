// Summary statistics with confidence intervals: the standard deviations and 95% intervals of
// the paper's Table I (Bruce & Veloso 2003, section II) and the mean with its t interval.
// Pure functions on a span of samples; bad input (too few samples, NaN or infinity, a level
// outside (0, 1)) throws patlab::InputError.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

namespace patlab::stats {

// Standard deviation s (divisor n - 1) with its confidence interval under a normal model:
// (n-1) s^2 / sigma^2 ~ chi^2_{n-1}, so
//   lower = s * sqrt((n-1) / chi2_quantile(1 - alpha/2)), upper = s * sqrt((n-1) /
//   chi2_quantile(alpha/2)),
// alpha = 1 - level (e.g. NIST/SEMATECH e-Handbook 1.3.5.8; quantiles from Boost.Math).
struct StdWithCi {
  double std = 0.0;    // sample standard deviation, divisor n - 1 (numpy ddof=1), data units
  double lower = 0.0;  // lower end of the interval, data units
  double upper = 0.0;  // upper end of the interval, data units
  double level = 0.95;
  std::size_t n = 0;
};

// Mean with the Student-t interval mean -+ t_{1-alpha/2, n-1} s / sqrt(n).
struct MeanWithCi {
  double mean = 0.0;
  double lower = 0.0;
  double upper = 0.0;
  double level = 0.95;
  std::size_t n = 0;
};

// Arithmetic mean; needs n >= 1.
double Mean(std::span<const double> x);
// Sample standard deviation with divisor n - 1 (two-pass); needs n >= 2.
double SampleStd(std::span<const double> x);

// Mean and sample standard deviation (divisor n - 1) of one sample.
struct MeanAndStd {
  double mean = 0.0;
  double std = 0.0;
};
// Mean and SampleStd of each of up to 8 samples of equal length (>= 2, finite, otherwise
// InputError), with exactly their arithmetic: each sample's sums run in index order, so the
// results are bit-identical to Mean and SampleStd. The samples are read in one loop, so their
// addition chains overlap in the CPU instead of waiting for one another (the sums are latency
// bound: one add per value); out has one slot per sample.
void MeanAndStdOfEach(std::span<const std::span<const double>> samples, std::span<MeanAndStd> out);

// The moments of a sample that merge: count, mean and the sum of squared deviations from the
// mean (M2), so that a sample too large to hold is summarised block by block and the blocks
// combined in a fixed order (the runner, and `patlab merge` of trial-range shards, fold the
// same blocks in the same order and so get the same bits).
struct Moments {
  std::int64_t n = 0;
  double mean = 0.0;
  double m2 = 0.0;
  // Sample standard deviation sqrt(M2 / (n - 1)); NaN for n < 2.
  double Std() const;
};
// The Moments of each of up to 8 samples of equal length (>= 1, finite, otherwise InputError),
// two-pass with the arithmetic of Mean and SampleStd (sums in index order), so for one block
// Moments::Std() is bit-identical to SampleStd.
void MomentsOfEach(std::span<const std::span<const double>> samples, std::span<Moments> out);
// A planar error sample: x and y (the position error) and theta, of equal length.
struct PlanarSample {
  std::span<const double> x, y, theta;
};
// The moments of a planar sample: those of x, y and theta, those of the radial error
// r = sqrt(x^2 + y^2), and sum_sq, the sum of x^2 + y^2 (the radial RMS).
struct PlanarMoments {
  Moments x, y, theta, radial;
  double sum_sq = 0.0;
};
// PlanarMoments of each of up to 4 planar samples (every column of the same length >= 1; x, y and
// theta finite, otherwise the InputError of MomentsOfEach, naming the first bad column in the
// order sample 0's x, y, theta, sample 1's x, ...). Each moment is the plain two-pass definition,
// every sum in index order: mean = (sum of v) / n, m2 = sum of (v - mean) * (v - mean) with each
// product rounded (never fused with the addition); for the radial error x^2 + y^2 is computed as
// fma(x, x, y * y) where the target has FMA (the contraction the compiler applied to the former
// per-estimator loops), else as the rounded sum, and sum_sq adds these values in index order.
// All the samples' sums (5 a sample in the first pass, 4 in the second) run in one loop, so that
// the CPU overlaps their addition chains; the squares, roots and deviations are computed for a
// tile of values at a time in loops the compiler vectorises.
void PlanarMomentsOfEach(std::span<const PlanarSample> samples, std::span<PlanarMoments> out);
// At most this many samples at once (one per estimator of a run).
inline constexpr std::size_t kMaxPlanarSamples = 5;
// One tile of the second pass of PlanarMomentsOfEach: trials [first, first + count) of every
// sample, with sample k's radial errors r = sqrt(x^2 + y^2) of those trials in radial[k][0, count),
// as the moments computed them (x^2 + y^2 by the rule above).
struct PlanarTile {
  std::size_t first = 0, count = 0;
  std::array<const double*, kMaxPlanarSamples> radial{};
};
// PlanarMomentsOfEach (the same results, bit for bit) that shows each tile of its second pass to
// `visit`, in index order, once the tile's values of every sample have been read: visit may then
// overwrite those elements of the samples' arrays. A caller that needs the radial errors after
// the moments (the runner's paired Wilcoxon tests) gets them without a pass and square roots of
// its own.
void PlanarMomentsOfEach(std::span<const PlanarSample> samples, std::span<PlanarMoments> out,
                         const std::function<void(const PlanarTile&)>& visit);
// The moments of the union of two disjoint samples (Chan, Golub & LeVeque 1979, eq. 2.1):
// delta = mean_b - mean_a, mean = mean_a + delta n_b / n, M2 = M2_a + M2_b + delta^2 n_a n_b / n.
// Combining with an empty side returns the other side unchanged.
Moments CombineMoments(const Moments& a, const Moments& b);

// level: confidence level in (0, 1); 0.95 gives the paper's 95% intervals. Needs n >= 2.
StdWithCi StdWithConfidence(std::span<const double> x, double level = 0.95);
// The same interval for a std estimated elsewhere with `dof` degrees of freedom (> 0), e.g. a
// std pooled over two axes (2 (n - 1) dof). n is left 0.
StdWithCi StdConfidenceInterval(double std, double dof, double level = 0.95);
MeanWithCi MeanWithConfidence(std::span<const double> x, double level = 0.95);

namespace detail {
// Throws InputError unless every value is finite; `what` names the sample in the message.
void RequireFinite(std::span<const double> x, const char* what);
}  // namespace detail

}  // namespace patlab::stats

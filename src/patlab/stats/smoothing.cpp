#include "patlab/stats/smoothing.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/gaussian.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {

namespace {
// The kernel's half holds floor(truncate_sigmas * sigma_samples + 0.5) + 1 weights: with these
// bounds at most 10^6 + 1 (8 MB), where sigma 1e300 asked for more than a vector can hold.
constexpr double kMaxSigmaSamples = 100000.0;
constexpr double kMaxTruncateSigmas = 10.0;
}  // namespace

std::vector<OptionsProblem> Check(const SmoothingOptions& options) {
  OptionsChecker check;
  check.NonNegative("sigma_samples", options.sigma_samples)
      .Require("sigma_samples", options.sigma_samples, !(options.sigma_samples > kMaxSigmaSamples),
               "at most 100000 samples (the kernel's size is bounded)")
      .Positive("truncate_sigmas", options.truncate_sigmas)
      .Require("truncate_sigmas", options.truncate_sigmas,
               !(options.truncate_sigmas > kMaxTruncateSigmas), "at most 10");
  return check.Take();
}

void Validate(const SmoothingOptions& options) { ThrowFirstProblem(Check(options)); }

std::vector<double> GaussianKernel(const SmoothingOptions& options) {
  Validate(options);
  return GaussianHalfKernel(options.sigma_samples, options.truncate_sigmas);
}

double ResidualStdFactor(const SmoothingOptions& options) {
  const std::vector<double> w = GaussianKernel(options);
  if (w.size() == 1) return 0.0;
  double sum_sq = w[0] * w[0];
  for (std::size_t k = 1; k < w.size(); ++k) sum_sq += 2.0 * w[k] * w[k];
  return std::sqrt(1.0 - 2.0 * w[0] + sum_sq);
}

double ResidualAutocorrelation(const SmoothingOptions& options, std::size_t lag) {
  const std::vector<double> half = GaussianKernel(options);
  if (half.size() == 1) return 0.0;
  const auto radius = static_cast<std::ptrdiff_t>(half.size()) - 1;
  auto w = [&](std::ptrdiff_t j) {
    const std::ptrdiff_t a = j < 0 ? -j : j;
    return a > radius ? 0.0 : half[static_cast<std::size_t>(a)];
  };
  const auto k = static_cast<std::ptrdiff_t>(lag);
  double cross = 0.0, sum_sq = 0.0;
  for (std::ptrdiff_t j = -radius; j <= radius; ++j) {
    cross += w(j) * w(j + k);
    sum_sq += w(j) * w(j);
  }
  const double c0 = 1.0 - 2.0 * w(0) + sum_sq;
  const double ck = lag == 0 ? c0 : -2.0 * w(k) + cross;
  return ck / c0;
}

std::vector<double> GaussianSmooth(std::span<const double> x, const SmoothingOptions& options) {
  const std::vector<double> w = GaussianKernel(options);
  if (x.empty()) throw InputError("cannot smooth an empty series; expected at least one sample");
  detail::RequireFinite(x, "series");
  const auto radius = static_cast<std::ptrdiff_t>(w.size()) - 1;
  if (radius == 0) return {x.begin(), x.end()};

  const auto n = static_cast<std::ptrdiff_t>(x.size());
  // Index into the reflected extension: period 2n, mirrored in the second half.
  auto at = [&](std::ptrdiff_t i) {
    std::ptrdiff_t m = i % (2 * n);
    if (m < 0) m += 2 * n;
    if (m >= n) m = 2 * n - 1 - m;
    return x[static_cast<std::size_t>(m)];
  };
  std::vector<double> out(x.size());
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double acc = x[static_cast<std::size_t>(i)] * w[0];
    if (i >= radius && i + radius < n) {
      for (std::ptrdiff_t k = 1; k <= radius; ++k) {
        acc += (x[static_cast<std::size_t>(i - k)] + x[static_cast<std::size_t>(i + k)]) *
               w[static_cast<std::size_t>(k)];
      }
    } else {
      for (std::ptrdiff_t k = 1; k <= radius; ++k) {
        acc += (at(i - k) + at(i + k)) * w[static_cast<std::size_t>(k)];
      }
    }
    out[static_cast<std::size_t>(i)] = acc;
  }
  return out;
}

std::vector<double> SmoothingResiduals(std::span<const double> x, const SmoothingOptions& options) {
  std::vector<double> r = GaussianSmooth(x, options);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = x[i] - r[i];
  return r;
}

double Autocorrelation(std::span<const double> x, std::size_t lag) {
  if (lag >= x.size()) {
    throw InputError("autocorrelation at lag " + std::to_string(lag) + " needs more than " +
                     std::to_string(lag) + " samples, got " + std::to_string(x.size()) +
                     "; expected a lag shorter than the series");
  }
  detail::RequireFinite(x, "series");
  const double mean = Mean(x);
  double num = 0.0, den = 0.0;
  for (std::size_t t = 0; t < x.size(); ++t) den += (x[t] - mean) * (x[t] - mean);
  for (std::size_t t = 0; t + lag < x.size(); ++t) num += (x[t] - mean) * (x[t + lag] - mean);
  if (den == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return num / den;
}

}  // namespace patlab::stats

#include "patlab/stats/summary.h"

#include <algorithm>
#include <array>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/options.h"
#include "patlab/stats/summary_internal.h"

namespace patlab::stats {
namespace detail {

void RequireFinite(std::span<const double> x, const char* what) {
  // A pass without an early exit, which the compiler vectorises; the slow loop below only runs to
  // name the first bad value.
  constexpr double kMax = std::numeric_limits<double>::max();
  unsigned bad = 0;
  for (const double v : x) bad |= std::fabs(v) <= kMax ? 0U : 1U;
  if (bad == 0) return;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) {
      throw InputError(std::string(what) + " value " + std::to_string(i + 1) + " is " +
                       (std::isnan(x[i]) ? "NaN" : "infinite") + "; expected finite numbers");
    }
  }
}

void RequireCount(std::span<const double> x, std::size_t min_n, const char* what) {
  if (x.size() < min_n) {
    throw InputError(std::string(what) + " needs at least " + std::to_string(min_n) +
                     " samples, got " + std::to_string(x.size()) + "; expected at least " +
                     std::to_string(min_n));
  }
}

}  // namespace detail

namespace {

using detail::RequireCount;

void RequireLevel(double level) {
  ThrowFirstProblem(OptionsChecker().InOpenRange("level", level, 0.0, 1.0).problems());
}

// The chi-square quantiles of the std interval (NIST e-Handbook 1.3.5.8): alpha / 2 and
// 1 - alpha / 2 with alpha = 1 - level. Boost's root finding costs tens of microseconds at
// 10^5 degrees of freedom, and the simulator asks for the same two (dof, level) pairs at every
// point, so each thread keeps the last few; the values are the same either way.
struct ChiSquaredQuantiles {
  double dof = -1.0, level = -1.0;
  double low = 0.0, high = 0.0;
};
const ChiSquaredQuantiles& Quantiles(double dof, double level) {
  constexpr int kEntries = 4;
  thread_local std::array<ChiSquaredQuantiles, kEntries> cache;
  thread_local int next = 0;
  for (const ChiSquaredQuantiles& q : cache) {
    if (q.dof == dof && q.level == level) return q;
  }
  ChiSquaredQuantiles& q = cache[next];
  next = (next + 1) % kEntries;
  const double alpha = 1.0 - level;
  const boost::math::chi_squared chi2(dof);
  q.low = boost::math::quantile(chi2, alpha / 2);
  q.high = boost::math::quantile(boost::math::complement(chi2, alpha / 2));
  q.dof = dof;
  q.level = level;
  return q;
}

}  // namespace

double Mean(std::span<const double> x) {
  RequireCount(x, 1, "the mean");
  double sum = 0.0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

double SampleStd(std::span<const double> x) {
  RequireCount(x, 2, "the standard deviation");
  const double mean = Mean(x);
  double sum_sq = 0.0;
  for (double v : x) sum_sq += (v - mean) * (v - mean);
  return std::sqrt(sum_sq / static_cast<double>(x.size() - 1));
}

namespace {

// M samples at once; see MomentsOfEach.
template <int M>
void MomentsInterleaved(const double* const* x, std::size_t n, Moments* out) {
  double sum[M] = {};
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < M; ++c) sum[c] += x[c][i];
  }
  double mean[M];
  for (int c = 0; c < M; ++c) mean[c] = sum[c] / static_cast<double>(n);
  double sum_sq[M] = {};
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < M; ++c) sum_sq[c] += (x[c][i] - mean[c]) * (x[c][i] - mean[c]);
  }
  for (int c = 0; c < M; ++c) {
    out[c] = Moments{static_cast<std::int64_t>(n), mean[c], sum_sq[c]};
  }
}

}  // namespace

double Moments::Std() const {
  if (n < 2) return std::nan("");
  return std::sqrt(m2 / static_cast<double>(n - 1));
}

void MomentsOfEach(std::span<const std::span<const double>> samples, std::span<Moments> out) {
  constexpr std::size_t kMaxSamples = 8;
  PATLAB_CHECK(samples.size() <= kMaxSamples && out.size() == samples.size());
  if (samples.empty()) return;
  const std::size_t n = samples[0].size();
  const double* x[kMaxSamples] = {};
  for (std::size_t c = 0; c < samples.size(); ++c) {
    PATLAB_CHECK(samples[c].size() == n);
    RequireCount(samples[c], 1, "the moments");
    detail::RequireFinite(samples[c], "sample");
    x[c] = samples[c].data();
  }
  for (std::size_t c = 0; c < samples.size(); c += 4) {
    switch (std::min<std::size_t>(4, samples.size() - c)) {
      case 1:
        MomentsInterleaved<1>(x + c, n, &out[c]);
        break;
      case 2:
        MomentsInterleaved<2>(x + c, n, &out[c]);
        break;
      case 3:
        MomentsInterleaved<3>(x + c, n, &out[c]);
        break;
      default:
        MomentsInterleaved<4>(x + c, n, &out[c]);
        break;
    }
  }
}

Moments CombineMoments(const Moments& a, const Moments& b) {
  if (b.n == 0) return a;
  if (a.n == 0) return b;
  const double na = static_cast<double>(a.n), nb = static_cast<double>(b.n);
  const double n = na + nb;
  const double delta = b.mean - a.mean;
  return Moments{a.n + b.n, a.mean + delta * (nb / n), a.m2 + b.m2 + delta * delta * (na * nb / n)};
}

void MeanAndStdOfEach(std::span<const std::span<const double>> samples, std::span<MeanAndStd> out) {
  PATLAB_CHECK(out.size() == samples.size());
  for (const std::span<const double> s : samples) RequireCount(s, 2, "the standard deviation");
  Moments m[8];
  MomentsOfEach(samples, std::span<Moments>(m, samples.size()));
  for (std::size_t c = 0; c < samples.size(); ++c) out[c] = MeanAndStd{m[c].mean, m[c].Std()};
}

StdWithCi StdWithConfidence(std::span<const double> x, double level) {
  RequireLevel(level);
  RequireCount(x, 2, "the standard deviation");
  detail::RequireFinite(x, "sample");
  StdWithCi out;
  out.n = x.size();
  out.level = level;
  const StdWithCi interval =
      StdConfidenceInterval(SampleStd(x), static_cast<double>(x.size() - 1), level);
  out.std = interval.std;
  out.lower = interval.lower;
  out.upper = interval.upper;
  return out;
}

StdWithCi StdConfidenceInterval(double std, double dof, double level) {
  RequireLevel(level);
  if (!(dof > 0.0)) {
    throw InputError("the std interval needs degrees of freedom > 0, got " + FormatNumber(dof) +
                     "; expected a positive number of degrees of freedom");
  }
  StdWithCi out;
  out.level = level;
  out.std = std;
  const ChiSquaredQuantiles& q = Quantiles(dof, level);
  out.lower = std * std::sqrt(dof / q.high);
  out.upper = std * std::sqrt(dof / q.low);
  return out;
}

MeanWithCi MeanWithConfidence(std::span<const double> x, double level) {
  RequireLevel(level);
  RequireCount(x, 2, "the mean confidence interval");
  detail::RequireFinite(x, "sample");
  MeanWithCi out;
  out.n = x.size();
  out.level = level;
  out.mean = Mean(x);
  const double s = SampleStd(x);
  const boost::math::students_t t(static_cast<double>(x.size() - 1));
  // Student-t interval for the mean.
  const double half_width = boost::math::quantile(boost::math::complement(t, (1.0 - level) / 2)) *
                            s / std::sqrt(static_cast<double>(x.size()));
  out.lower = out.mean - half_width;
  out.upper = out.mean + half_width;
  return out;
}

}  // namespace patlab::stats

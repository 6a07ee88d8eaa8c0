#include "patlab/stats/summary.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <string>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/options.h"

namespace patlab::stats {
namespace detail {

void RequireFinite(std::span<const double> x, const char* what) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) {
      throw InputError(std::string(what) + " value " + std::to_string(i + 1) + " is " +
                       (std::isnan(x[i]) ? "NaN" : "infinite") + "; expected finite numbers");
    }
  }
}

}  // namespace detail

namespace {

void RequireCount(std::span<const double> x, std::size_t min_n, const char* what) {
  if (x.size() < min_n) {
    throw InputError(std::string(what) + " needs at least " + std::to_string(min_n) +
                     " samples, got " + std::to_string(x.size()));
  }
}

void RequireLevel(double level) {
  ThrowFirstProblem(OptionsChecker().InOpenRange("level", level, 0.0, 1.0).problems());
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
    throw InputError("the std interval needs degrees of freedom > 0, got " + FormatNumber(dof));
  }
  StdWithCi out;
  out.level = level;
  out.std = std;
  const double alpha = 1.0 - level;
  const boost::math::chi_squared chi2(dof);
  // Chi-square interval for sigma: NIST e-Handbook 1.3.5.8.
  const double q_low = boost::math::quantile(chi2, alpha / 2);
  const double q_high = boost::math::quantile(boost::math::complement(chi2, alpha / 2));
  out.lower = std * std::sqrt(dof / q_high);
  out.upper = std * std::sqrt(dof / q_low);
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

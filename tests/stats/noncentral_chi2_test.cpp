#include "patlab/stats/noncentral_chi2.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../expect_error.h"
#include "patlab/core/error.h"

namespace patlab::stats {
namespace {

// scipy 1.10.1, computed once:
//   /usr/bin/python3 -c "from scipy.stats import ncx2; print(repr(ncx2.cdf(10.0, 3, 5.0)))"
// and likewise for the other rows.
TEST(NoncentralChiSquared, CdfMatchesScipy) {
  EXPECT_NEAR(NoncentralChiSquaredCdf(10.0, 3, 5.0), 0.7066486477774525, 1e-12);
  EXPECT_NEAR(NoncentralChiSquaredCdf(29.87750390922517, 7, 65.0), 0.0011540244158925572, 1e-14);
  EXPECT_NEAR(NoncentralChiSquaredCdf(2.0, 1, 0.5), 0.7433025121441785, 1e-12);
  EXPECT_NEAR(NoncentralChiSquaredCdf(2.0, 1, 0.0), std::erf(1.0), 1e-14);  // chi^2_1: |N| <= 1.414
}

// The noncentrality with P(chi'^2(7, lambda) <= chi2_7^-1(0.9999)) = 1e-3 (scipy 1.10.1):
//   from scipy.stats import ncx2, chi2; from scipy.optimize import brentq
//   q = chi2.ppf(0.9999, 7); brentq(lambda l: ncx2.cdf(q, 7, l) - 0.001, 1e-9, 1e4, xtol=1e-14)
//   -> q = 29.87750390922517, lambda = 65.71324602910286
TEST(NoncentralChiSquared, NoncentralityForCdfMatchesScipy) {
  const double lambda = NoncentralityForCdf(7, 29.87750390922517, 0.001);
  EXPECT_NEAR(lambda, 65.71324602910286, 1e-6);
  EXPECT_NEAR(NoncentralChiSquaredCdf(29.87750390922517, 7, lambda), 0.001, 1e-12);
}

TEST(NoncentralChiSquared, RejectsBadArguments) {
  EXPECT_THROW(NoncentralChiSquaredCdf(1.0, 0.0, 1.0), InputError);
  EXPECT_THROW(NoncentralChiSquaredCdf(1.0, 2.0, -1.0), InputError);
  EXPECT_THROW(NoncentralityForCdf(3, 10.0, 0.0), InputError);
  // P(chi^2_3 <= 1) = 0.199: no noncentrality reaches p = 0.5.
  EXPECT_INPUT_ERROR(NoncentralityForCdf(3, 1.0, 0.5),
                     "noncentral chi-square: p is 0.5; expected 0 < p < 0.198748043099 (the "
                     "central chi-square's P(X <= x))");
}

}  // namespace
}  // namespace patlab::stats

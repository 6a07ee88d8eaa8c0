// The KS walks by sorting and by buckets (ks.cpp, ks_buckets.cpp) against the walk as first
// written, on samples that stress their plans and windows.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "../expect_error.h"
#include "ks_test_util.h"
#include "patlab/core/error.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/ks_internal.h"

namespace patlab::stats {
namespace {

using testing::ExpectSameExtremes;
using testing::Lcg;
using testing::StraightforwardExtremes;

TEST(Ks, BucketedAndSortedWalksAgreeWithTheStraightforwardOne) {
  Lcg rng{12345};
  const auto uniform = [&rng] { return rng.Uniform(); };
  const auto normal = [&rng] { return rng.Normal(); };
  // kinds: 0 normal, 1 shifted and scaled, 2 quantised (ties within and between samples, signed
  // zeros), 3 heavy tails (outliers 1000x), 4 constant, 5 two values, 6 the same values index by
  // index, 7 pairs that differ by rounding (two estimators that agree to 1e-13, as fast and ML do
  // on the Simple pattern), 8 the same values but one.
  for (int kind = 0; kind < 9; ++kind) {
    for (const auto& [n1, n2] :
         {std::pair{1, 1}, {3, 7}, {1000, 1000}, {5000, 3000}, {20000, 20000}}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n1 << "," << n2);
      std::vector<double> x(n1), y(n2);
      for (auto* v : {&x, &y}) {
        const double shift = v == &y && kind == 1 ? 0.05 : 0.0;
        for (double& z : *v) {
          z = normal() * (kind == 1 && v == &y ? 1.1 : 1.0) + shift;
          if (kind == 2) z = std::round(z * 8.0) / 8.0 * (uniform() < 0.5 ? 1.0 : -1.0);
          if (kind == 3 && uniform() < 0.01) z *= 1000.0;
          if (kind == 4) z = 2.5;
          if (kind == 5) z = uniform() < 0.3 ? -0.0 : 0.0;
        }
      }
      if (kind >= 6 && n1 == n2) {
        for (size_t k = 0; k < y.size(); ++k) {
          y[k] = kind == 7 ? x[k] * (1.0 + 1e-13 * (uniform() - 0.5)) : x[k];
        }
        if (kind == 8) y[y.size() / 2] += 0.5;
      }
      const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
      ExpectSameExtremes(detail::EcdfExtremesBySorting(x, y), want);
      ExpectSameExtremes(detail::EcdfExtremesByBuckets(x, y), want);
      if (n1 == n2) ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), want);
      const KsResult r =
          KsTwoSample(x, y, KsOptions{Alternative::kTwoSided, KsMethod::kAsymptotic});
      EXPECT_EQ(r.d, std::max(want.max_diff, std::clamp(-want.min_diff, 0.0, 1.0)));
    }
  }
}

// Samples larger than one window of walked values (2^18 a sample): the walks go window by window
// with bounded buffers. Pairs that differ by rounding make every bucket a walked one (the hard
// case), with windows breaking inside runs; quantised pairs add ties across window ends; one
// bucket holding more than a window (clustered values) is walked whole.
TEST(Ks, BucketedWalkInWindowsAgreesOnSamplesLargerThanAWindow) {
  Lcg rng{777};
  const auto uniform = [&rng] { return rng.Uniform(); };
  for (int kind = 0; kind < 3; ++kind) {
    for (const size_t n : {300000u, 700000u}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n);
      std::vector<double> x(n), y(n);
      for (size_t k = 0; k < n; ++k) {
        const double u = uniform() + uniform() + uniform() - 1.5;
        x[k] = kind == 1 ? std::round(u * 4096.0) / 4096.0 : u;
        if (kind == 2) x[k] = k % 10 == 0 ? u : 1.0;
        y[k] = kind == 1 ? (uniform() < 0.5 ? x[k] : x[k] + 1.0 / 4096.0)
                         : x[k] * (1.0 + 1e-13 * (uniform() - 0.5));
      }
      const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
      ExpectSameExtremes(detail::EcdfExtremesByBuckets(x, y), want);
      // The paired walk's check of the starts goes window by window here (more than 2^18 pairs
      // differ in kind 0).
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), want);
    }
  }
}

// The bucket walk's plan on the shapes that stress it, each against the straightforward walk:
// fig5-like samples that differ (std ratio 1.1, a few heavy tails so the walked buckets are full
// and in many runs: more runs than the ranges that cover them in Extract), n1 != n2, sizes that
// are no multiple of the chunks and flag words, the extremes at the first bucket (ties at the
// smallest value) and at the last (ties at the largest, which the clamp puts there), values
// quantised coarser than a bucket (ties, most buckets empty), signed zeros among them, and two
// samples that cross many times (the walked buckets scattered over the whole range).
TEST(Ks, BucketWalkAgreesWithTheStraightforwardOneOnShapesThatStressItsPlan) {
  Lcg rng{2026};
  const auto uniform = [&rng] { return rng.Uniform(); };
  const auto normal = [&rng] { return rng.Normal(); };
  for (int kind = 0; kind < 7; ++kind) {
    for (const auto& [n1, n2] :
         {std::pair{100000, 100000}, {100003, 99997}, {60001, 4099}, {2047, 30011}}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n1 << "," << n2);
      std::vector<double> x(n1), y(n2);
      for (size_t k = 0; k < x.size(); ++k) {
        x[k] = normal() * 1.1;
        if (k % 50 == 0) x[k] *= 3.0;
      }
      for (size_t k = 0; k < y.size(); ++k) {
        y[k] = normal();
        if (k % 50 == 0) y[k] *= 3.0;
      }
      switch (kind) {
        case 1:  // extremes at the first bucket: a third of x at the smallest value
          for (size_t k = 0; k < x.size(); k += 3) x[k] = -20.0;
          break;
        case 2:  // extremes at the last bucket: a third of y at the largest value
          for (size_t k = 0; k < y.size(); k += 3) y[k] = 20.0;
          break;
        case 3:  // quantised coarser than a bucket, signed zeros
          for (auto* v : {&x, &y}) {
            for (double& z : *v) {
              z = std::round(z * 16.0) / 16.0;
              if (z == 0.0 && uniform() < 0.5) z = -0.0;
            }
          }
          break;
        case 4:  // y paired with x (fast and ML in the same trials), n1 != n2 cut short
          for (size_t k = 0; k < y.size(); ++k) y[k] = x[k % x.size()] / 1.1 + 0.05 * normal();
          break;
        case 5:  // the same distribution: F1 - F2 crosses zero many times, flat extremes
          for (size_t k = 0; k < y.size(); ++k) y[k] = normal() * 1.1;
          break;
        case 6:  // sine-shaped shifts: several local extremes of equal height
          for (double& z : y) z += 0.02 * std::sin(z * 12.0);
          break;
        default:
          break;
      }
      const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
      ExpectSameExtremes(detail::EcdfExtremesByBuckets(x, y), want);
      ExpectSameExtremes(detail::EcdfExtremesByBuckets(y, x), StraightforwardExtremes(y, x));
      // As EcdfExtremesByPairs calls it: the range given, not computed by the walk.
      const auto [x_lo, x_hi] = std::minmax_element(x.begin(), x.end());
      const auto [y_lo, y_hi] = std::minmax_element(y.begin(), y.end());
      ExpectSameExtremes(detail::internal::ExtremesByBucketsIn(x, y, std::min(*x_lo, *y_lo),
                                                               std::max(*x_hi, *y_hi)),
                         want);
      if (n1 == n2) ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), want);
    }
  }
}

// More walked values than a window holds with n1 != n2 (the windows break inside runs and between
// them, and the buffers keep their bound): samples of one distribution whose F1 - F2 stays small,
// on a grid so that ties cross the window ends, a cluster where one bucket alone holds more than a
// window, and x = every value of y twice (F1 = F2 at every group end: every bucket walked), also
// with one copy moved by an ulp.
TEST(Ks, BucketWalkInWindowsAgreesWhenTheSizesDiffer) {
  Lcg rng{99};
  const auto uniform = [&rng] { return rng.Uniform(); };
  for (int kind = 0; kind < 5; ++kind) {
    SCOPED_TRACE(::testing::Message() << "kind " << kind);
    std::vector<double> x(300001), y(150001);
    for (auto* v : {&x, &y}) {
      for (double& z : *v) {
        z = uniform() + uniform() - 1.0;
        if (kind == 1) z = std::round(z * 65536.0) / 65536.0;
        if (kind == 2 && uniform() < 0.3) z = 0.25 + 1e-12 * uniform();
      }
    }
    // y a thinned copy of x: F1 - F2 is noise of order 1/sqrt(n), many buckets reach it.
    for (size_t k = 0; k < y.size(); ++k) y[k] = kind == 2 ? y[k] : x[2 * k];
    if (kind >= 3) {
      y.resize(100003);
      x.resize(2 * y.size());
      for (size_t k = 0; k < y.size(); ++k) {
        x[2 * k] = y[k];
        x[2 * k + 1] = kind == 4 && k % 7 == 0 ? std::nextafter(y[k], 2.0) : y[k];
      }
    }
    const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
    ExpectSameExtremes(detail::EcdfExtremesByBuckets(x, y), want);
    ExpectSameExtremes(detail::EcdfExtremesByBuckets(y, x), StraightforwardExtremes(y, x));
  }
}

}  // namespace
}  // namespace patlab::stats

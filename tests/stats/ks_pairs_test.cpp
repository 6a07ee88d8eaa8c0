// The KS walk of pairs (ks_pairs.cpp, ks_pairs_starts.cpp) against the walk as first written: pairs
// that differ by rounding, planted overlaps of the starts, and pairs that really differ.
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

// The paired walk on the pairs its shortcut is made for and on those that must defeat it: pairs
// that differ by rounding (a few ulps, or relative 1e-13, some equal), so that c stays in
// {-1, 0, 1} and the largest rounding step decides; the same on a coarse grid (ties across pairs,
// touching intervals); every pair going up (no down pair: the bucket walk); estimators that really
// differ; signed zeros; one pair apart; two pairs apart where the largest rounding step is never
// reached (the shortcut gives up); intervals that overlap without sharing a start (the starts'
// check must reject them).
TEST(Ks, PairedWalkAgreesWithTheStraightforwardOneOnPairsThatDifferByRounding) {
  Lcg rng{4242};
  const auto uniform = [&rng] { return rng.Uniform(); };
  const auto normal = [&rng] { return rng.Normal(); };
  const auto ulps = [](double v, int steps) {
    for (int k = 0; k < steps; ++k) v = std::nextafter(v, 1e300);
    for (int k = 0; k > steps; --k) v = std::nextafter(v, -1e300);
    return v;
  };
  for (int kind = 0; kind < 9; ++kind) {
    for (const size_t n : {2100u, 20000u, 100000u}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n);
      std::vector<double> x(n), y(n);
      for (size_t k = 0; k < n; ++k) {
        const double u = uniform();
        x[k] = normal() * 3.0;
        if (kind == 2) x[k] = std::round(x[k] * 64.0) / 64.0;
        if (kind == 5) x[k] = u < 0.4 ? -0.0 : u < 0.8 ? 0.0 : x[k];
        switch (kind) {
          case 0:
            y[k] = ulps(x[k], static_cast<int>(uniform() * 7.0) - 3);
            break;
          case 1:
            y[k] = u < 0.6 ? x[k] : x[k] * (1.0 + 1e-13 * (uniform() - 0.5));
            break;
          case 2:
            y[k] = ulps(x[k], static_cast<int>(uniform() * 5.0) - 2);
            break;
          case 3:
            y[k] = ulps(x[k], 1);
            break;
          case 4:
            y[k] = x[k] + 0.1 * normal();
            break;
          case 5:
            y[k] = u < 0.5 ? -x[k] : ulps(x[k], u < 0.7 ? 1 : -1);
            break;
          case 6:
            y[k] = x[k];
            break;
          case 7:
            y[k] = ulps(x[k], -1);
            break;
          default:
            // Below -4 (the lowest 9%, far from where the largest rounding step can occur):
            // intervals of about 1e-9 starting within 1e-9 of one of a few values, which overlap
            // (c reaches 2 and -2) without sharing a start; above, one ulp either way.
            if (x[k] < -4.0) {
              x[k] = std::round(x[k] * 20.0) / 20.0 + 1e-9 * uniform();
              y[k] = x[k] + (u < 0.5 ? 1e-9 : -1e-9) * (0.5 + uniform());
            } else {
              y[k] = ulps(x[k], u < 0.5 ? 1 : -1);
            }
            break;
        }
      }
      if (kind == 6) y[n / 3] = x[n / 3] + 1e-9;
      if (kind == 6 && n == 20000) {
        // One pair up, one down, both at small values: c = 1 and -1 are reached only at ranks
        // where the rounding does not give the largest step, so the shortcut must give up.
        const size_t low = static_cast<size_t>(std::min_element(x.begin(), x.end()) - x.begin());
        y[n / 3] = x[n / 3];
        y[low] = ulps(x[low], 1);
        const size_t next = low == 0 ? 1 : 0;
        y[next] = ulps(x[next], -1);
      }
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), StraightforwardExtremes(x, y));
      ExpectSameExtremes(detail::EcdfExtremesByPairs(y, x), StraightforwardExtremes(y, x));
    }
  }
}

// The paired walk's check of the starts goes in the order of a 22-bit key of each start (2^22
// cells over the range) and compares neighbours exactly: pairs of intervals a few ulps wide that
// overlap (c reaches 2, so the shortcut's +-1/n answer would be wrong) with their starts in
// adjacent cells, in one cell in the samples' reverse order, or at the same value, and placed far
// from the rank where the largest rounding step occurs (where the walked region would see them);
// starts close but apart (the shortcut stands); a range so wide that every start has key 0;
// above 2^16 differing pairs (the check goes window by window), an overlap straddling the first
// window's end; pairs apart across every coarse bin boundary. Values in [0, 1] with 0 and 1
// present, so that the key of a start s is floor(s * 2^22) and its coarse bin floor(s * 4096).
enum class Plant {
  kAdjacentCells,
  kOneCellReversed,
  kEqualStarts,
  kCloseButApart,
  kHugeRange,
  kAcrossWindows,
  kAcrossBins
};

double Ulps(double v, int steps) {
  for (int k = 0; k < steps; ++k) v = std::nextafter(v, 2.0);
  for (int k = 0; k > steps; --k) v = std::nextafter(v, -1.0);
  return v;
}

// G = max over i of fl(i/n) - fl((i - 1)/n), and the first i that reaches it.
std::pair<double, size_t> LargestStep(size_t n) {
  double best = -1.0, previous = 0.0;
  size_t at = 0;
  for (size_t i = 1; i <= n; ++i) {
    const double q = static_cast<double>(i) / static_cast<double>(n);
    if (q - previous > best) best = q - previous, at = i;
    previous = q;
  }
  return {best, at};
}

struct PlantedPairs {
  std::vector<double> x, y;
  size_t next = 2;  // pairs 0 and 1 hold the range's ends
  void Up(double start, int width) {
    x[next] = start;
    y[next++] = Ulps(start, width);
  }
};

// Clusters of planted pairs at 40 cell boundaries b = j / 2^22 near `far`.
void PlantInCells(Plant plant, double far, PlantedPairs* p) {
  for (int c = 0; c < 40; ++c) {
    const double b = std::round(far * 0x1p22 + 1000.0 * c) * 0x1p-22;
    if (plant == Plant::kAdjacentCells || plant == Plant::kHugeRange) {
      p->Up(Ulps(b, -2), 4), p->Up(b, 3);  // [b - 2u, b + 2u), [b, b + 3u): cells j - 1, j
    } else if (plant == Plant::kOneCellReversed) {
      p->Up(Ulps(b, 6), 3), p->Up(Ulps(b, 4), 4);  // the later start first, both in cell j
    } else if (plant == Plant::kEqualStarts) {
      p->Up(Ulps(b, 4), 2), p->Up(Ulps(b, 4), 1);
    } else if (plant == Plant::kCloseButApart) {  // widest 2u: starts 5u apart
      p->Up(Ulps(b, -3), 2), p->Up(Ulps(b, 2), 1), p->Up(Ulps(b, 7), 2);
    }
  }
}

// One overlapping pair of intervals straddling the end of the first window: the first coarse
// bin B whose starts would bring the window above 2^16; [b - 2u, b + 2u) ends the window,
// [b, b + 3u) begins the next, with b = B / 4096. Only the check across windows can see it.
void PlantAcrossWindows(size_t at, PlantedPairs* p) {
  p->Up(0.5, 0), p->Up(0.5, 0);
  std::vector<size_t> per_bin(4096, 0);
  for (size_t j = 0; j < p->x.size(); ++j) {
    if (p->x[j] != p->y[j]) ++per_bin[static_cast<size_t>(std::min(p->x[j], p->y[j]) * 4096.0)];
  }
  size_t bin = 0, below = 0;
  while (below + per_bin[bin] <= (size_t{1} << 16)) below += per_bin[bin++];
  ASSERT_LE(below + 1, size_t{1} << 16);  // the lower start stays in the first window
  const double b = static_cast<double>(bin) / 4096.0;
  ASSERT_GT(std::abs(b - static_cast<double>(at) / static_cast<double>(p->x.size())), 0.1);
  p->next = 2;
  p->Up(Ulps(b, -2), 4), p->Up(b, 3);
}

// Pairs apart whose values lie in adjacent coarse bins, at every bin boundary (up and down in
// turn), so also where the walked region begins and ends: y's counts at the bins' ends differ
// from x's there.
void PlantAcrossBins(PlantedPairs* p) {
  for (int bin = 1; bin < 4096; ++bin) {
    const double b = bin / 4096.0;
    if (bin % 2 == 0) {
      p->Up(Ulps(b, -1), 2);
    } else {
      p->x[p->next] = Ulps(b, 1), p->y[p->next++] = Ulps(b, -1);
    }
  }
}

TEST(Ks, PairedWalkChecksStartsByKeyBitForBit) {
  for (const Plant plant :
       {Plant::kAdjacentCells, Plant::kOneCellReversed, Plant::kEqualStarts, Plant::kCloseButApart,
        Plant::kHugeRange, Plant::kAcrossWindows, Plant::kAcrossBins}) {
    const bool windows = plant == Plant::kAcrossWindows, bins = plant == Plant::kAcrossBins;
    for (const size_t n : windows ? std::vector<size_t>{300000}
                          : bins  ? std::vector<size_t>{20000}
                                  : std::vector<size_t>{2100, 20000}) {
      SCOPED_TRACE(::testing::Message() << "plant " << static_cast<int>(plant) << " n " << n);
      Lcg rng{static_cast<uint64_t>(31 + static_cast<int>(plant))};
      PlantedPairs p{std::vector<double>(n), std::vector<double>(n)};
      for (size_t k = 0; k < n; ++k) {
        p.x[k] = rng.Uniform();
        const double u = rng.Uniform();
        p.y[k] = u < 0.15 ? Ulps(p.x[k], 1) : u < 0.3 ? Ulps(p.x[k], -1) : p.x[k];
      }
      p.x[0] = p.y[0] = 0.0;
      p.x[1] = p.y[1] = plant == Plant::kHugeRange ? 1e300 : 1.0;
      const auto [g, at] = LargestStep(n);
      // Away from the rank of the largest step (uniform values: rank / n).
      const double far = static_cast<double>(at) / static_cast<double>(n) < 0.5 ? 0.8 : 0.2;
      PlantInCells(plant, far, &p);
      if (windows) PlantAcrossWindows(at, &p);
      if (bins) PlantAcrossBins(&p);
      const detail::EcdfExtremes want = StraightforwardExtremes(p.x, p.y);
      if (plant == Plant::kCloseButApart || bins) {
        EXPECT_EQ(want.max_diff, g);  // the shortcut stands
      } else {
        EXPECT_GT(want.max_diff, 1.5 * g);  // the overlap decides: the shortcut must not
      }
      ExpectSameExtremes(detail::EcdfExtremesByPairs(p.x, p.y), want);
      ExpectSameExtremes(detail::EcdfExtremesByPairs(p.y, p.x), StraightforwardExtremes(p.y, p.x));
    }
  }
}

// Samples equal index by index are compared and scanned a block of 1,024 values at a time: the
// extremes (0 at the smallest value, -0.0 before +0.0) wherever the smallest value lies, and
// samples equal in every block but the last (or but one value) take the paired walk's answer.
TEST(Ks, PairedWalkOfEqualSamplesAgreesWithTheStraightforwardOne) {
  Lcg rng{77};
  for (const size_t n : {size_t{1}, size_t{1023}, size_t{1024}, size_t{1025}, size_t{5000}}) {
    for (const size_t at : {size_t{0}, n / 2, n - 1}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " smallest at " << at);
      std::vector<double> x(n);
      for (double& v : x) v = rng.Normal();
      x[at] = -10.0;
      const std::vector<double> y = x;
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), StraightforwardExtremes(x, y));
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, x), StraightforwardExtremes(x, x));
      std::vector<double> zeros(n, 0.0);
      zeros[at] = -0.0;
      ExpectSameExtremes(detail::EcdfExtremesByPairs(zeros, zeros),
                         StraightforwardExtremes(zeros, zeros));
      std::vector<double> last = x;
      last[n - 1] = std::nextafter(last[n - 1], 100.0);
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, last), StraightforwardExtremes(x, last));
    }
  }
}

// The starts of the pairs that differ, copied 8 pairs at a time where the build has AVX-512 (the
// differing ones compressed to the front of each store): the plain definition's values bit for
// bit, in order, appended after the m already there, for every length around the vector width,
// pairs that differ by an ulp either way, equal pairs, signed zeros (equal, so never a start; which
// of them a min returns is std::min's choice) and a NaN (differs, as x != y says); nothing written
// beyond the count + kStartsSlack - 1.
TEST(Ks, DifferingStartsAreThoseOfThePlainDefinition) {
  using detail::internal::CopyDifferingStarts;
  using detail::internal::kStartsSlack;
  Lcg rng{4242};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t c = 0; c <= 40; ++c) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<double> x(c), y(c);
      for (size_t k = 0; k < c; ++k) {
        x[k] = rng.Normal();
        const double u = rng.Uniform();
        y[k] = u < 0.3   ? std::nextafter(x[k], 10.0)
               : u < 0.6 ? std::nextafter(x[k], -10.0)
               : u < 0.9 ? x[k]
                         : rng.Normal();
        if (rng.Uniform() < 0.05) x[k] = -0.0, y[k] = 0.0;
        if (rng.Uniform() < 0.02) y[k] = nan;
      }
      const size_t m0 = trial % 3;  // starts already in the buffer
      std::vector<double> want(m0, 7.0);
      for (size_t k = 0; k < c; ++k) {
        if (x[k] != y[k]) want.push_back(std::min(x[k], y[k]));
      }
      const double sentinel = 1234.5;
      std::vector<double> got(want.size() + kStartsSlack + 4, sentinel);
      std::fill(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(m0), 7.0);
      const size_t m = CopyDifferingStarts(x.data(), y.data(), c, got.data(), m0);
      SCOPED_TRACE(::testing::Message() << "c " << c << " trial " << trial);
      ASSERT_EQ(m, want.size());
      for (size_t i = 0; i < m; ++i) {
        EXPECT_EQ(std::bit_cast<uint64_t>(got[i]), std::bit_cast<uint64_t>(want[i])) << i;
      }
      for (size_t i = m + kStartsSlack; i < got.size(); ++i) EXPECT_EQ(got[i], sentinel) << i;
    }
  }
}

// The pair summary runs in 8 lanes and a tail: a non-finite value in the lanes or in the tail,
// in either sample or in both (the same array, or equal arrays), gives the messages of the check
// of each sample.
TEST(Ks, PairedWalkRejectsNonFiniteValuesInLanesAndTail) {
  for (const size_t n : {4096u, 4099u}) {
    for (const size_t at : {size_t{0}, size_t{9}, n - 1}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " at " << at);
      std::vector<double> x(n), y(n);
      for (size_t k = 0; k < n; ++k) x[k] = y[k] = static_cast<double>(k % 97) * 0.25;
      y[n / 2] += 1.0;
      const std::string where = " value " + std::to_string(at + 1) + " is ";
      std::vector<double> bad = x;
      bad[at] = std::nan("");
      EXPECT_INPUT_ERROR(KsTwoSample(x, bad), "sample 2" + where + "NaN; expected finite numbers");
      EXPECT_INPUT_ERROR(KsTwoSample(bad, y), "sample 1" + where + "NaN; expected finite numbers");
      EXPECT_INPUT_ERROR(KsTwoSample(bad, bad),
                         "sample 1" + where + "NaN; expected finite numbers");
      const std::vector<double> copy = bad;
      EXPECT_INPUT_ERROR(KsTwoSample(bad, copy),
                         "sample 1" + where + "NaN; expected finite numbers");
      bad[at] = -std::numeric_limits<double>::infinity();
      EXPECT_INPUT_ERROR(KsTwoSample(y, bad),
                         "sample 2" + where + "infinite; expected finite numbers");
    }
  }
}

// Paired samples that really differ (fast and ML on Butterfly and SSL-standard): a look at 256
// pairs sends them to the bucket walk over a range guessed from those pairs, counted in one pass
// over the pairs, the walk planned on the integer counts. Against the straightforward walk: sizes
// at the paired walk's threshold (n1 + n2 = 4096) and around the chunks, fig5-like errors, heavy
// tails (values beyond the guess in the end buckets, which are then walked), the extremes out in
// the tails (within the guess, and beyond it), ties and signed zeros, sorted samples (the guess
// misses most of the range: the counts again over the range found), a constant sample against a
// varying one.
TEST(Ks, PairsThatReallyDifferAgreeWithTheStraightforwardWalk) {
  Lcg rng{31337};
  const auto uniform = [&rng] { return rng.Uniform(); };
  const auto normal = [&rng] { return rng.Normal(); };
  for (int kind = 0; kind < 8; ++kind) {
    for (const size_t n : {2048u, 2049u, 4099u, 100000u, 100003u}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n);
      std::vector<double> x(n), y(n);
      for (size_t k = 0; k < n; ++k) {
        x[k] = normal();
        y[k] = x[k] / 1.1 + 0.4 * normal();
        switch (kind) {
          case 1:  // heavy tails: a ratio of normals (Cauchy), both samples
            x[k] = normal() / normal();
            y[k] = 0.9 * x[k] + 0.5 * normal() / normal();
            break;
          case 2:  // the extremes out in the tails: 2% of the pairs far beyond the rest
            if (k % 50 == 7) x[k] = 40.0 + normal(), y[k] = 41.5 + normal();
            break;
          case 3:  // ties within and across samples, signed zeros
            x[k] = std::round(x[k] * 4.0) / 4.0;
            y[k] = std::round(y[k] * 4.0) / 4.0;
            if (x[k] == 0.0 && uniform() < 0.5) x[k] = -0.0;
            if (y[k] == 0.0 && uniform() < 0.5) y[k] = -0.0;
            break;
          case 5:  // a constant sample against a varying one
            x[k] = 0.25;
            break;
          case 6:  // widely different scales
            y[k] = 1e6 * x[k] + normal();
            break;
          case 7:  // 1% of the pairs beyond the guess (none in the sampled blocks), the extremes
                   // among them: in the end bucket, walked because it is not empty
            if (k % 100 == 99 && k % (n / 8) >= 32)
              x[k] = 100.0 + normal(), y[k] = 100.5 + normal();
            break;
          default:
            break;
        }
      }
      if (kind == 4) {  // sorted: the sampled blocks miss the top eighth and more
        std::sort(x.begin(), x.end());
        std::sort(y.begin(), y.end());
        for (size_t k = 0; k < n; ++k) y[k] += 0.1 * static_cast<double>(k % 3);
      }
      const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
      ExpectSameExtremes(detail::EcdfExtremesByPairs(x, y), want);
      ExpectSameExtremes(detail::EcdfExtremesByPairs(y, x), StraightforwardExtremes(y, x));
      const KsResult r =
          KsTwoSample(x, y, KsOptions{Alternative::kTwoSided, KsMethod::kAsymptotic});
      EXPECT_EQ(r.d, std::max(want.max_diff, std::clamp(-want.min_diff, 0.0, 1.0)));
    }
  }
}

// The bucket walk over a guessed range, any guess: good, too narrow (many values in the end
// buckets: counted again over the range found), beside every value, inside one bucket, inverted,
// of zero width, too wide or too small for a finite scale, NaN. Every one gives the walk's result.
TEST(Ks, PairsBucketWalkAgreesWhateverTheGuessedRange) {
  Lcg rng{8080};
  const auto normal = [&rng] { return rng.Normal(); };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const size_t n : {3000u, 65536u}) {
    std::vector<double> x(n), y(n);
    for (size_t k = 0; k < n; ++k) {
      x[k] = normal() * 2.0;
      y[k] = x[k] * 0.8 + normal();
      if (k % 97 == 0) y[k] *= 30.0;  // a few far out: the end buckets of most guesses
    }
    const detail::EcdfExtremes want = StraightforwardExtremes(x, y);
    for (const auto& [lo, hi] : {std::pair{-3.0, 3.0},
                                 {-8.0, 8.0},
                                 {-0.5, 0.5},
                                 {100.0, 200.0},
                                 {-200.0, -100.0},
                                 {0.1, 0.1 + 1e-15},
                                 {3.0, -3.0},
                                 {1.0, 1.0},
                                 {-1e308, 1e308},
                                 {0.0, 1e-310},
                                 {std::nan(""), 1.0},
                                 {-kInf, kInf}}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " guess " << lo << ", " << hi);
      ExpectSameExtremes(detail::internal::ExtremesOfPairsByBuckets(x, y, lo, hi), want);
    }
  }
}

// Non-finite values where the look sends the pairs to the bucket walk: NaN and infinities go to
// the end buckets, which are then walked and checked; the messages are RequireFinite's (sample 1
// first, the first bad value), also when the bad value is in a sampled block (the look then leaves
// it to the summary pass), outside them, in the last pair, or in both samples.
TEST(Ks, PairsThatReallyDifferRejectNonFiniteValues) {
  Lcg rng{5150};
  const auto normal = [&rng] { return rng.Normal(); };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const size_t n : {2048u, 100001u}) {
    std::vector<double> x(n), y(n);
    for (size_t k = 0; k < n; ++k) x[k] = normal(), y[k] = 0.9 * x[k] + 0.5 * normal();
    for (const size_t at : {size_t{0}, size_t{5}, n / 2 + 3, n / 2 + 100, n - 1}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " at " << at);
      const std::string where = " value " + std::to_string(at + 1) + " is ";
      for (const double bad : {std::nan(""), kInf, -kInf}) {
        const std::string what = std::isnan(bad) ? "NaN" : "infinite";
        std::vector<double> bx = x, by = y;
        bx[at] = bad;
        EXPECT_INPUT_ERROR(KsTwoSample(bx, y),
                           "sample 1" + where + what + "; expected finite numbers");
        by[at] = bad;
        EXPECT_INPUT_ERROR(KsTwoSample(x, by),
                           "sample 2" + where + what + "; expected finite numbers");
        EXPECT_INPUT_ERROR(KsTwoSample(bx, by),
                           "sample 1" + where + what + "; expected finite numbers");
        // y bad here, x bad further on: sample 1's message
        if (at + 1 < n) {
          std::vector<double> later = x;
          later[at + 1] = bad;
          EXPECT_INPUT_ERROR(KsTwoSample(later, by), "sample 1 value " + std::to_string(at + 2) +
                                                         " is " + what +
                                                         "; expected finite numbers");
        }
        EXPECT_INPUT_ERROR(detail::internal::ExtremesOfPairsByBuckets(bx, y, -0.1, 0.1),
                           "sample 1" + where + what + "; expected finite numbers");
        EXPECT_INPUT_ERROR(detail::internal::ExtremesOfPairsByBuckets(x, by, -4.0, 4.0),
                           "sample 2" + where + what + "; expected finite numbers");
      }
    }
  }
}

}  // namespace
}  // namespace patlab::stats

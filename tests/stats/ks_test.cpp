#include "patlab/stats/ks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "../expect_error.h"
#include "fixtures.h"
#include "patlab/core/error.h"
#include "patlab/stats/ks_internal.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Ks, MatchesScipyFixtures) {
  int checked = 0;
  for (const auto& c : Fixtures().at("ks")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const std::vector<double> y = Sample(c.at("y"));
    KsOptions options;
    options.alternative = ParseAlternative(c.at("alternative").get<std::string>());
    options.method = ParseKsMethod(c.at("method").get<std::string>());
    const KsResult r = KsTwoSample(x, y, options);
    const auto& e = c.at("expect");
    EXPECT_EQ(r.d, e.at("d").get<double>());  // the statistic is compared exactly
    EXPECT_EQ(KsMethodName(r.method_used), e.at("method_used").get<std::string>());
    EXPECT_EQ(r.sign, e.at("sign").get<int>());
    EXPECT_REL_NEAR(r.p_value, e.at("p").get<double>(), 1e-9);
    if (e.contains("p_lattice_int")) {
      EXPECT_REL_NEAR(r.p_value, e.at("p_lattice_int").get<double>(), 1e-9);
    }
    const double n1 = static_cast<double>(x.size()), n2 = static_cast<double>(y.size());
    EXPECT_DOUBLE_EQ(r.d_scaled, std::sqrt(n1 * n2 / (n1 + n2)) * r.d);
    EXPECT_GE(r.p_value, 0.0);
    EXPECT_LE(r.p_value, 1.0);
    ++checked;
  }
  EXPECT_GE(checked, 70);
}

TEST(Ks, FixturesReachTinyPValuesAndLargeN) {
  double smallest = 1.0;
  std::size_t largest = 0;
  for (const auto& c : Fixtures().at("ks")) {
    smallest = std::min(smallest, c.at("expect").at("p").get<double>());
    const auto& x = c.at("x");
    largest = std::max(largest, x.contains("gen") ? x.at("gen").at("n").get<std::size_t>()
                                                  : x.at("values").size());
  }
  EXPECT_LT(smallest, 1e-200);
  EXPECT_EQ(largest, 100000u);
}

TEST(Ks, ComparesEcdfsAfterAllTiedValues) {
  // After value 2 both ECDFs have moved: F1 = 1, F2 = 1/2. Stepping one element at a time
  // would see F1 = 1, F2 = 0 and report D = 1.
  const std::vector<double> x = {1.0, 2.0};
  const std::vector<double> y = {2.0, 3.0};
  const KsResult r = KsTwoSample(x, y);
  EXPECT_EQ(r.d, 0.5);
  EXPECT_EQ(r.location, 1.0);
  // Every order of 2 + 2 values has |F1 - F2| = 1/2 after its first step, so p = 1.
  EXPECT_EQ(r.p_value, 1.0);
}

TEST(Ks, KolmogorovLimitMatchesScipy) {
  for (const auto& row : Fixtures().at("kolmogorov_limit")) {
    const double x = row.at(0).get<double>();
    SCOPED_TRACE(x);
    EXPECT_REL_NEAR(KolmogorovSurvival(x), row.at(1).get<double>(), 1e-10);
  }
  EXPECT_EQ(KolmogorovSurvival(0.0), 1.0);
  EXPECT_EQ(KolmogorovSurvival(-1.0), 1.0);
}

TEST(Ks, ExactFormsAgreeByHand) {
  // n1 = n2 = 2: 6 equally likely orders, D = 1 only for xxyy and yyxx.
  EXPECT_DOUBLE_EQ(KsExactEqualTwoSided(2, 2), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(KsExactEqualOneSided(2, 2), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(KsExactLattice(2, 2, 2, true), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(KsExactLattice(2, 2, 2, false), 1.0 / 6.0);
  // The reflection sum and the lattice recursion are independent algorithms.
  for (int n : {3, 10, 57}) {
    for (int h = 1; h <= n; h += 2) {
      SCOPED_TRACE(n * 1000 + h);
      EXPECT_REL_NEAR(KsExactLattice(n, n, h, true), KsExactEqualTwoSided(n, h), 1e-11);
      EXPECT_REL_NEAR(KsExactLattice(n, n, h, false), KsExactEqualOneSided(n, h), 1e-11);
    }
  }
  EXPECT_EQ(KsExactLattice(5, 7, 0, true), 1.0);
}

TEST(Ks, ExactFallsBackToAsymptoticBeyondTheLatticeLimit) {
  std::vector<double> x(20000), y(15001);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i) * 0.5;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = static_cast<double>(i) * 0.6 + 0.1;
  KsOptions options;
  options.method = KsMethod::kExact;
  const KsResult r = KsTwoSample(x, y, options);
  EXPECT_EQ(r.method_used, KsMethod::kAsymptotic);
  EXPECT_REL_NEAR(r.p_value, KolmogorovSurvival(r.d_scaled), 1e-15);
}

TEST(Ks, RejectsEmptyAndNonFiniteInput) {
  const std::vector<double> empty;
  const std::vector<double> one = {1.0};
  const std::vector<double> bad = {1.0, std::nan("")};
  EXPECT_INPUT_ERROR(
      KsTwoSample(one, empty),
      "the KS test needs two non-empty samples, got 1 and 0 values; expected at least one "
      "value in each");
  EXPECT_INPUT_ERROR(KsTwoSample(one, bad), "sample 2 value 2 is NaN; expected finite numbers");
  // Equal sizes large enough for the paired walk, which checks the values in its own pass: the
  // same messages, also when both samples are the same array.
  std::vector<double> big(3000, 1.0), big_bad = big;
  big_bad[2500] = std::numeric_limits<double>::infinity();
  EXPECT_INPUT_ERROR(KsTwoSample(big, big_bad),
                     "sample 2 value 2501 is infinite; expected finite numbers");
  EXPECT_INPUT_ERROR(KsTwoSample(big_bad, big_bad),
                     "sample 1 value 2501 is infinite; expected finite numbers");
  EXPECT_INPUT_ERROR(ParseKsMethod("approx"),
                     "method is \"approx\"; expected \"auto\", \"exact\" or \"asymp\"");
  EXPECT_EQ(ParseKsMethod("asymp"), KsMethod::kAsymptotic);
  EXPECT_EQ(KsMethodName(KsMethod::kAsymptotic), "asymp");
}

// The walk as first written: std::sort, then one tied value at a time.
detail::EcdfExtremes StraightforwardExtremes(std::vector<double> a, std::vector<double> b) {
  // -0.0 before +0.0, as SortAscending orders them.
  const auto less = [](double p, double q) {
    return p < q || (p == q && std::signbit(p) && !std::signbit(q));
  };
  std::sort(a.begin(), a.end(), less);
  std::sort(b.begin(), b.end(), less);
  const size_t n1 = a.size(), n2 = b.size();
  detail::EcdfExtremes e;
  size_t i = 0, j = 0;
  while (i < n1 || j < n2) {
    const double v = (j >= n2 || (i < n1 && a[i] <= b[j])) ? a[i] : b[j];
    while (i < n1 && a[i] == v) ++i;
    while (j < n2 && b[j] == v) ++j;
    const double diff = static_cast<double>(i) / static_cast<double>(n1) -
                        static_cast<double>(j) / static_cast<double>(n2);
    if (diff > e.max_diff) e.max_diff = diff, e.max_loc = v;
    if (diff < e.min_diff) e.min_diff = diff, e.min_loc = v;
  }
  return e;
}

void ExpectSameExtremes(const detail::EcdfExtremes& got, const detail::EcdfExtremes& want) {
  EXPECT_EQ(got.max_diff, want.max_diff);
  EXPECT_EQ(got.min_diff, want.min_diff);
  EXPECT_EQ(got.max_loc, want.max_loc);
  EXPECT_EQ(got.min_loc, want.min_loc);
  EXPECT_EQ(std::signbit(got.max_loc), std::signbit(want.max_loc));
  EXPECT_EQ(std::signbit(got.min_loc), std::signbit(want.min_loc));
}

// A small deterministic generator for the walks' tests (an LCG; Box-Muller for normals).
struct Lcg {
  uint64_t state;
  double Uniform() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) * 0x1p-53;
  }
  double Normal() {
    const double u = Uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * Uniform());
  }
};

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

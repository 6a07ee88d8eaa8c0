// Speed of the statistics on data-point-sized samples (100,000 trials a data point).
// Target: KS on two 100,000-sample sets and Wilcoxon on 100,000 pairs, each under 50 ms.
//   build-stats/bench/stats_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "patlab/stats/ks.h"
#include "patlab/stats/ks_internal.h"
#include "patlab/stats/sort.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace {

// Irwin-Hall(4) samples from splitmix64: roughly normal, deterministic, no library dependence.
std::vector<double> Sample(std::uint64_t seed, std::size_t n, double shift, double quantum) {
  std::vector<double> out(n);
  for (double& v : out) {
    double s = 0.0;
    for (int i = 0; i < 4; ++i) {
      seed += 0x9E3779B97F4A7C15ULL;
      std::uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
      z ^= z >> 31;
      s += static_cast<double>(z >> 11) * 0x1p-53;
    }
    v = shift + 2.0 * (s - 2.0);
    if (quantum > 0) v = static_cast<double>(static_cast<std::int64_t>(v / quantum)) * quantum;
  }
  return out;
}

void BM_KsTwoSample(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<double> x = Sample(1, n, 0.0, 0.0);
  const std::vector<double> y = Sample(2, n, 0.01, 0.0);
  patlab::stats::KsOptions options;
  options.method = static_cast<patlab::stats::KsMethod>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(x, y, options));
}
BENCHMARK(BM_KsTwoSample)
    ->ArgNames({"n", "method"})
    ->Args({100000, static_cast<int>(patlab::stats::KsMethod::kAuto)})
    ->Args({100000, static_cast<int>(patlab::stats::KsMethod::kExact)})
    ->Unit(benchmark::kMillisecond);

// Two estimators that agree to rounding (fast and ML on Simple, Linear and Triangle): y is x moved
// by 0 to 3 units in the last place, either way. F1 - F2 stays within +-1/n, the hard case.
void BM_KsRoundingOnly(benchmark::State& state) {
  const std::vector<double> x = Sample(1, 100000, 0.0, 0.0);
  std::vector<double> y = x;
  std::uint64_t z = 12345;
  for (double& v : y) {
    z = z * 6364136223846793005ULL + 1442695040888963407ULL;
    const int steps = static_cast<int>((z >> 33) % 7) - 3;
    for (int k = 0; k < steps; ++k) v = std::nextafter(v, 1e300);
    for (int k = 0; k > steps; --k) v = std::nextafter(v, -1e300);
  }
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(x, y));
}
BENCHMARK(BM_KsRoundingOnly)->Unit(benchmark::kMillisecond);

// Two estimators that really differ, in the same trials (fast and ML on Butterfly): y is x plus
// a third of an independent error.
void BM_KsPairedEstimatorsDiffer(benchmark::State& state) {
  const std::vector<double> x = Sample(1, 100000, 0.0, 0.0);
  const std::vector<double> e = Sample(2, 100000, 0.0, 0.0);
  std::vector<double> y(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) y[k] = x[k] + e[k] / 3.0;
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(x, y));
}
BENCHMARK(BM_KsPairedEstimatorsDiffer)->Unit(benchmark::kMillisecond);

// fig5's KS tests whose samples really differ (fast vs ML on Butterfly and SSL-standard), the
// bucket walk's case: 100,000 errors each, ML slightly better than fast (std ratio ~1.1). paired:
// in the same trials (fast = ML + an independent part, as the runner's samples), else independent.
// tails: every 50th trial's errors 3x larger in both (wider range, so ~40 values in the walked
// buckets, in 10-15 runs, as measured on fig5's samples; without: ~15 a bucket in 4-8 runs).
struct Fig5Samples {
  std::vector<double> fast, ml;
  double lo, hi;
};
Fig5Samples Fig5Like(bool paired, bool tails) {
  Fig5Samples s;
  s.ml = Sample(11, 100000, 0.0, 0.0);
  const std::vector<double> extra = Sample(12, 100000, 0.0, 0.0);
  s.fast.resize(s.ml.size());
  for (std::size_t k = 0; k < s.ml.size(); ++k) {
    s.fast[k] = paired ? s.ml[k] + 0.458 * extra[k] : 1.1 * extra[k];
  }
  for (std::size_t k = 0; tails && k < s.ml.size(); k += 50) s.ml[k] *= 3.0, s.fast[k] *= 3.0;
  const auto [lo1, hi1] = std::minmax_element(s.fast.begin(), s.fast.end());
  const auto [lo2, hi2] = std::minmax_element(s.ml.begin(), s.ml.end());
  s.lo = std::min(*lo1, *lo2), s.hi = std::max(*hi1, *hi2);
  return s;
}

void BM_KsFig5Differ(benchmark::State& state) {
  const Fig5Samples s = Fig5Like(state.range(0) != 0, state.range(1) != 0);
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(s.fast, s.ml));
}
BENCHMARK(BM_KsFig5Differ)
    ->ArgNames({"paired", "tails"})
    ->Args({1, 0})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

// The bucket walk alone on the samples above (the range given, as EcdfExtremesByPairs gives it).
void BM_KsBucketWalkFig5(benchmark::State& state) {
  const Fig5Samples s = Fig5Like(state.range(0) != 0, state.range(1) != 0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        patlab::stats::detail::internal::ExtremesByBucketsIn(s.fast, s.ml, s.lo, s.hi));
  }
}
BENCHMARK(BM_KsBucketWalkFig5)
    ->ArgNames({"paired", "tails"})
    ->Args({1, 0})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Args({0, 1})
    ->Unit(benchmark::kMillisecond);

void BM_KsExactLattice(benchmark::State& state) {
  const std::vector<double> x = Sample(1, 5000, 0.0, 0.0);
  const std::vector<double> y = Sample(2, 4000, 0.01, 0.0);
  patlab::stats::KsOptions options;
  options.method = patlab::stats::KsMethod::kExact;
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(x, y, options));
}
BENCHMARK(BM_KsExactLattice)->Unit(benchmark::kMillisecond);

void BM_Wilcoxon(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const double quantum = state.range(1) ? 0x1p-8 : 0.0;  // quantised: ties and zeros
  const std::vector<double> x = Sample(3, n, 0.0, quantum);
  const std::vector<double> y = Sample(4, n, 0.01, quantum);
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::WilcoxonSignedRank(x, y));
}
BENCHMARK(BM_Wilcoxon)
    ->ArgNames({"n", "ties"})
    ->Args({100000, 0})
    ->Args({100000, 1})
    ->Unit(benchmark::kMillisecond);

// The runner's call: the in-place test with the caller's scratch on differences computed before
// (the copy of the 100,000 differences into the work array, ~0.03 ms, is timed with it).
void BM_WilcoxonInPlace(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const double quantum = state.range(1) ? 0x1p-8 : 0.0;
  const std::vector<double> x = Sample(3, n, 0.0, quantum);
  const std::vector<double> y = Sample(4, n, 0.01, quantum);
  std::vector<double> d(n), work(n), scratch(n);
  for (std::size_t i = 0; i < n; ++i) d[i] = x[i] - y[i];
  for (auto _ : state) {
    std::copy(d.begin(), d.end(), work.begin());
    benchmark::DoNotOptimize(patlab::stats::WilcoxonSignedRankInPlace(work, scratch));
  }
}
BENCHMARK(BM_WilcoxonInPlace)
    ->ArgNames({"n", "ties"})
    ->Args({100000, 0})
    ->Args({100000, 1})
    ->Unit(benchmark::kMillisecond);

// The runner's Wilcoxon on heavy-tailed differences like fig5's |error| fast - ML (Butterfly,
// SSL-standard): magnitudes 1e-3 x exp(3 N(0, 1)), spread over ~40 binades and piled up near
// their median, with random signs; in place with the caller's scratch (copy of d timed with it).
void BM_WilcoxonHeavyTails(benchmark::State& state) {
  const std::vector<double> u = Sample(8, 100000, 0.0, 0.0);  // roughly N(0, 2/3)
  const std::vector<double> s = Sample(9, 100000, 0.0, 0.0);
  std::vector<double> d(u.size()), work(u.size()), scratch(u.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    d[i] = (s[i] < 0 ? -1e-3 : 1e-3) * std::exp(3.0 * 1.2247 * u[i]);
  }
  for (auto _ : state) {
    std::copy(d.begin(), d.end(), work.begin());
    benchmark::DoNotOptimize(patlab::stats::WilcoxonSignedRankInPlace(work, scratch));
  }
}
BENCHMARK(BM_WilcoxonHeavyTails)->Unit(benchmark::kMillisecond);

// One sort of 100,000 doubles (the unit of work of the tests above), and the same with
// std::sort for scale.
void BM_SortAscending(benchmark::State& state) {
  const std::vector<double> x = Sample(6, 100000, 0.0, 0.0);
  std::vector<double> v(x.size());
  for (auto _ : state) {
    std::copy(x.begin(), x.end(), v.begin());
    if (state.range(0) != 0) {
      patlab::stats::SortAscending(v);
    } else {
      std::sort(v.begin(), v.end());
    }
    benchmark::DoNotOptimize(v.data());
  }
}
BENCHMARK(BM_SortAscending)->ArgName("radix")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_StdWithCi(benchmark::State& state) {
  const std::vector<double> x = Sample(5, 100000, 0.0, 0.0);
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::StdWithConfidence(x));
}
BENCHMARK(BM_StdWithCi)->Unit(benchmark::kMillisecond);

// fig5's rounding tests, as the runner makes them: errors of about 0.01-0.05 m (fast and ML on
// Simple, Linear and Triangle) where ~30% of the pairs differ by 1 to 3 ulps either way (arg 0),
// and the same arrays' values in two arrays (arg 1: x and y on Linear and Triangle).
void BM_KsFig5Rounding(benchmark::State& state) {
  const std::size_t n = 100000;
  std::vector<double> x = Sample(7, n, 0.0, 0.0);
  for (double& v : x) v *= 0.02;
  std::vector<double> y = x;
  if (state.range(0) == 0) {
    std::uint64_t z = 99;
    for (double& v : y) {
      z = z * 6364136223846793005ULL + 1442695040888963407ULL;
      const auto r = static_cast<int>((z >> 33) % 20);  // 0-5 of 20 differ: 30%
      const int steps = r < 3 ? r + 1 : r < 6 ? 2 - r : 0;
      for (int k = 0; k < steps; ++k) v = std::nextafter(v, 1e300);
      for (int k = 0; k > steps; --k) v = std::nextafter(v, -1e300);
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(patlab::stats::KsTwoSample(x, y));
}
BENCHMARK(BM_KsFig5Rounding)->ArgName("same")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
// The moments of one data point: 2 estimators x 100,000 trials, each with x, y, theta and the
// radial error sqrt(x^2 + y^2). Arg 0: the former per-estimator passes (MomentsOfEach on x, y,
// theta, then two loops for the radial error, as the runner had them); arg 1: one
// PlanarMomentsOfEach call for both estimators.
void BM_PointMoments(benchmark::State& state) {
  constexpr std::size_t kN = 100000;
  std::vector<std::vector<double>> columns;
  for (std::uint64_t c = 0; c < 6; ++c) columns.push_back(Sample(20 + c, kN, 0.001 * c, 0.0));
  const patlab::stats::PlanarSample samples[2] = {{columns[0], columns[1], columns[2]},
                                                  {columns[3], columns[4], columns[5]}};
  for (auto _ : state) {
    if (state.range(0) != 0) {
      patlab::stats::PlanarMoments m[2];
      patlab::stats::PlanarMomentsOfEach(samples, m);
      benchmark::DoNotOptimize(m);
      continue;
    }
    for (const patlab::stats::PlanarSample& s : samples) {
      const std::span<const double> xyt[3] = {s.x, s.y, s.theta};
      patlab::stats::Moments m[3];
      patlab::stats::MomentsOfEach(xyt, m);
      double sum_sq = 0.0, sum = 0.0;
      for (std::size_t k = 0; k < kN; ++k) {
        const double sq = s.x[k] * s.x[k] + s.y[k] * s.y[k];
        sum_sq += sq;
        sum += std::sqrt(sq);
      }
      const double mean = sum / static_cast<double>(kN);
      double m2 = 0.0;
      for (std::size_t k = 0; k < kN; ++k) {
        const double r = std::sqrt(s.x[k] * s.x[k] + s.y[k] * s.y[k]);
        m2 += (r - mean) * (r - mean);
      }
      benchmark::DoNotOptimize(m);
      benchmark::DoNotOptimize(sum_sq);
      benchmark::DoNotOptimize(m2);
    }
  }
}
BENCHMARK(BM_PointMoments)->ArgName("planar")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

// Two-sample Kolmogorov-Smirnov test, following scipy.stats.ks_2samp (scipy 1.10) except where
// docs/stats.md lists a deliberate difference. Used to compare the error samples of
// two estimators (paper section IV: fast vs ML estimation, "no statistically significant
// differences could be detected with a Kolmogorov-Smirnov test").
//
// The statistic compares the two empirical CDFs after all tied values (a value shared by both
// samples moves both CDFs before they are compared), as scipy does with searchsorted(side=right).
// p-values assume continuous distributions (no correction for ties), as in scipy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "patlab/stats/hypothesis.h"

namespace patlab::stats {

enum class KsMethod {
  kAuto,        // kExact when max(n1, n2) <= kKsMaxAutoExactN, else kAsymptotic (scipy's rule)
  kExact,       // exact null distribution; falls back to kAsymptotic beyond the size limits below
  kAsymptotic,  // two-sided: limiting Kolmogorov law; one-sided: Hodges' (1958) eq. 5.3
};

inline constexpr EnumNames<KsMethod, 3> kKsMethodNames{{{
    {KsMethod::kAuto, "auto"},
    {KsMethod::kExact, "exact"},
    {KsMethod::kAsymptotic, "asymp"},
}}};
// "auto", "exact", "asymp".
inline std::string_view KsMethodName(KsMethod method) { return NameOf(method, kKsMethodNames); }
// Throws InputError "method is \"x\"; expected \"auto\", \"exact\" or \"asymp\"".
inline KsMethod ParseKsMethod(std::string_view name) {
  return ParseName(name, kKsMethodNames, "method");
}

// kAuto uses the exact distribution up to this many samples in the larger set (scipy MAX_AUTO_N).
inline constexpr std::size_t kKsMaxAutoExactN = 10000;
// For n1 != n2 the exact distribution is a lattice-path recursion costing n1 * n2 steps
// (~1 ns each); above this many steps kExact falls back to kAsymptotic (reported in
// KsResult::method_used). n1 == n2 uses closed forms of cost O(n) and has no limit.
inline constexpr std::uint64_t kKsMaxExactLatticeSteps = 200'000'000;

struct KsOptions {
  Alternative alternative = Alternative::kTwoSided;
  KsMethod method = KsMethod::kAuto;
};

struct KsResult {
  // two-sided: max |F1 - F2|; greater: max(F1 - F2); less: max(F2 - F1) (clipped at 0).
  // In exact mode it is rounded to the lattice, h / lcm(n1, n2), as scipy does.
  double d = 0.0;
  double d_scaled = 0.0;  // sqrt(n1 n2 / (n1 + n2)) * d, the argument of the limiting law
  double p_value = 1.0;   // always in [0, 1]
  KsMethod method_used = KsMethod::kExact;  // kExact or kAsymptotic, never kAuto
  int sign = 1;                             // +1 if d is max(F1 - F2), -1 if max(F2 - F1)
  double location = 0.0;  // a sample value where the maximum is reached (first one)
  std::size_t n1 = 0;
  std::size_t n2 = 0;
};

// x, y: the two samples (copied and sorted; any order). Both must be non-empty and finite,
// otherwise InputError. O((n1 + n2) log(n1 + n2)) plus the p-value (see KsMethod).
KsResult KsTwoSample(std::span<const double> x, std::span<const double> y,
                     const KsOptions& options = {});

// The pieces, exposed for tests and for callers that already have the statistic.
// Survival function of the limiting Kolmogorov distribution, P(K > x) with
// K = sup |Brownian bridge| (Kolmogorov 1933; the two series of Feller 1948).
double KolmogorovSurvival(double x);
// Exact P(D >= h/n) for n1 = n2 = n, two-sided: reflection sum 2 sum_k (-1)^(k-1)
// C(2n, n-kh)/C(2n, n) (Gnedenko & Korolyuk 1951), in scipy's Horner form.
double KsExactEqualTwoSided(std::int64_t n, std::int64_t h);
// Exact P(D+ >= h/n) for n1 = n2 = n: C(2n, n-h)/C(2n, n) as a product.
double KsExactEqualOneSided(std::int64_t n, std::int64_t h);
// Exact P(D >= h/lcm) (two_sided) or P(D+ >= h/lcm) for any n1, n2 by the lattice-path
// recursion of Hodges (1958) carried on probabilities of leaving the band rather than path
// counts (Viehmann 2021, arXiv:2102.08037), so small p-values keep full relative accuracy.
double KsExactLattice(std::int64_t n1, std::int64_t n2, std::int64_t h, bool two_sided);

namespace detail {
// The extremes of F1 - F2 over the merged order of the two samples, compared only after all
// tied values, each with the sample value of the first group where it is reached (the walk of
// KsTwoSample). Two implementations with identical results, exposed for the tests:
struct EcdfExtremes {
  double max_diff = -1.0, min_diff = 1.0;
  double max_loc = 0.0, min_loc = 0.0;
};
// Sorts both samples whole and walks their merged order: O(n log n).
EcdfExtremes EcdfExtremesBySorting(std::span<const double> x, std::span<const double> y);
// Counts both samples into min((n1 + n2) / b, 2^15) buckets of equal width (b = sqrt(n1 + n2) / 72
// values a bucket, 2 to 16) between the smallest and the largest value, takes the ECDFs' counts at
// every bucket end, and copies out, sorts and walks only the buckets inside which F1 - F2 could
// reach its extremes (for continuous samples a few percent of them; all of them when the samples
// differ by rounding only); samples equal index by index need one pass. O(n) for continuous data,
// never worse than sorting. KsTwoSample uses it for n1 + n2 >= 4096 when n1 != n2 (and
// EcdfExtremesByPairs when its shortcut fails).
EcdfExtremes EcdfExtremesByBuckets(std::span<const double> x, std::span<const double> y);
// Samples of equal size, taken as pairs x[k], y[k] (two estimators' errors in the same trials):
// when the pairs that differ do so by intervals [min, max) that are pairwise apart (the case of
// estimators that agree to rounding), F1 - F2 is -1/n, 0 or 1/n up to rounding at every group
// end, its extremes are the largest rounding step, and a walk of a few hundred values from the
// rank where that step can first occur finds them (the derivation is in ks_pairs.cpp). Otherwise,
// and if that walk does not find them, EcdfExtremesByBuckets (samples that really differ go there
// at once, after a look at 256 pairs, counted in one pass over the pairs on a range guessed from
// them). Same results as the two above, bit for bit. KsTwoSample uses it for n1 = n2 and
// n1 + n2 >= 4096. It checks that the values are finite (InputError as KsTwoSample's); the other
// two expect finite values.
EcdfExtremes EcdfExtremesByPairs(std::span<const double> x, std::span<const double> y);
}  // namespace detail

}  // namespace patlab::stats

// Shared vocabulary of the hypothesis tests in stats/: which alternative is tested, and the
// parsing of its name (used by cli/ and by fixtures).
#pragma once

#include <string>
#include <string_view>

namespace patlab::stats {

// The alternative hypothesis, with scipy's meaning (scipy.stats.ks_2samp / wilcoxon, 1.10):
//  - kTwoSided: the distributions differ;
//  - kLess:     KS: the CDF of the first sample is below the second's somewhere (first tends to
//               larger values); Wilcoxon: the differences x - y are stochastically below zero;
//  - kGreater:  the opposite of kLess.
enum class Alternative { kTwoSided, kLess, kGreater };

// "two-sided", "less", "greater".
std::string_view AlternativeName(Alternative alternative);
// Inverse of AlternativeName; throws patlab::InputError naming the accepted values.
Alternative ParseAlternative(std::string_view name);

}  // namespace patlab::stats

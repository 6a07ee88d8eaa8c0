// Shared vocabulary of the hypothesis tests in stats/: which alternative is tested, and the
// parsing of its name (used by cli/ and by fixtures).
#pragma once

#include <string>
#include <string_view>

#include "patlab/core/enum_names.h"

namespace patlab::stats {

// The alternative hypothesis, with scipy's meaning (scipy.stats.ks_2samp / wilcoxon, 1.10):
//  - kTwoSided: the distributions differ;
//  - kLess:     KS: the CDF of the first sample is below the second's somewhere (first tends to
//               larger values); Wilcoxon: the differences x - y are stochastically below zero;
//  - kGreater:  the opposite of kLess.
enum class Alternative { kTwoSided, kLess, kGreater };
inline constexpr EnumNames<Alternative, 3> kAlternativeNames{{{
    {Alternative::kTwoSided, "two-sided"},
    {Alternative::kLess, "less"},
    {Alternative::kGreater, "greater"},
}}};

// "two-sided", "less", "greater".
inline std::string_view AlternativeName(Alternative alternative) {
  return NameOf(alternative, kAlternativeNames);
}
// Inverse of AlternativeName; throws patlab::InputError
// "alternative is \"both\"; expected \"two-sided\", \"less\" or \"greater\"".
inline Alternative ParseAlternative(std::string_view name) {
  return ParseName(name, kAlternativeNames, "alternative");
}

}  // namespace patlab::stats

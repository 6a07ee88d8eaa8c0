// Close names for "did you mean ...": a misspelt command, flag or data name is answered with
// the names it was probably meant to be.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace patlab {

// The optimal-string-alignment Damerau-Levenshtein distance: the fewest insertions, deletions,
// substitutions and swaps of two adjacent characters that turn `a` into `b` (no substring is
// edited twice). "trails" -> "trials" is 1, "sigma" -> "sigmas" is 1.
int EditDistance(std::string_view a, std::string_view b);

// The candidates `typed` was probably meant to be, best first: those at the smallest edit
// distance when it is at most 2 (and smaller than the typed name's length, so that "x" is not
// close to every one-letter name), else the one candidate `typed` is a prefix of, if unique.
// Empty when nothing is close.
std::vector<std::string> CloseNames(std::string_view typed,
                                    const std::vector<std::string>& candidates);

// "'a'", "'a' or 'b'", "'a', 'b' or 'c'": the names for a message.
std::string QuotedAlternatives(const std::vector<std::string>& names);

}  // namespace patlab

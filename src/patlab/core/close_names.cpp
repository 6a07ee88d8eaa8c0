#include "patlab/core/close_names.h"

#include <algorithm>
#include <climits>
#include <vector>

namespace patlab {

int EditDistance(std::string_view a, std::string_view b) {
  const size_t n = a.size(), m = b.size();
  // Three rows of the dynamic programme: the swap looks two rows back.
  std::vector<int> before(m + 1), previous(m + 1), current(m + 1);
  for (size_t j = 0; j <= m; ++j) previous[j] = static_cast<int>(j);
  for (size_t i = 1; i <= n; ++i) {
    current[0] = static_cast<int>(i);
    for (size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        current[j] = std::min(current[j], before[j - 2] + 1);
      }
    }
    before.swap(previous);
    previous.swap(current);
  }
  return previous[m];
}

std::vector<std::string> CloseNames(std::string_view typed,
                                    const std::vector<std::string>& candidates) {
  int best = INT_MAX;
  std::vector<std::string> close;
  for (const std::string& c : candidates) {
    const int d = EditDistance(typed, c);
    if (d > 2 || d >= static_cast<int>(typed.size()) || d > best) continue;
    if (d < best) close.clear();
    best = d;
    if (std::find(close.begin(), close.end(), c) == close.end()) close.push_back(c);
  }
  if (!close.empty() || typed.empty()) return close;
  for (const std::string& c : candidates) {
    if (c.starts_with(typed) && std::find(close.begin(), close.end(), c) == close.end()) {
      close.push_back(c);
    }
  }
  if (close.size() != 1) close.clear();
  return close;
}

std::string QuotedAlternatives(const std::vector<std::string>& names) {
  std::string text;
  for (size_t k = 0; k < names.size(); ++k) {
    if (k > 0) text += k + 1 == names.size() ? " or " : ", ";
    text += "'" + names[k] + "'";
  }
  return text;
}

}  // namespace patlab

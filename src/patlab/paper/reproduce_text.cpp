// The comparison of regenerated manifests and text files with the committed ones, and paper.md.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "patlab/core/format.h"
#include "patlab/io/csv.h"
#include "patlab/paper/reproduce.h"

namespace patlab::paper {

namespace {

// The manifest keys that say where the files were written, or where the inputs were read from.
void EraseRunAndPaths(nlohmann::json* j) {
  for (const char* key : {"outputs", "pattern_file"}) {
    j->erase(key);
  }
  if (j->contains("experiment")) {
    if ((*j)["experiment"].is_object()) {
      (*j)["experiment"].erase("file");
    } else {
      j->erase("experiment");
    }
  }
  if (j->contains("patterns") && (*j)["patterns"].is_array()) {
    for (nlohmann::json& p : (*j)["patterns"]) {
      if (p.is_object()) p.erase("file");
    }
  }
}

bool NumbersAgree(double x, double y) {
  return x == y || std::abs(x - y) <= 2e-9 * std::max(std::abs(x), std::abs(y)) + 1e-12;
}

// The first difference of two JSON values, "" if none (numbers within the file tolerance).
std::string FirstDifference(const nlohmann::json& a, const nlohmann::json& b,
                            const std::string& where) {
  if (a.is_number() && b.is_number()) {
    return NumbersAgree(a.get<double>(), b.get<double>())
               ? ""
               : where + " " + a.dump() + "; committed: " + b.dump();
  }
  if (a.type() != b.type() || (a.is_array() && a.size() != b.size()) ||
      (a.is_primitive() && a != b)) {
    return where + " " + a.dump() + "; committed: " + b.dump();
  }
  if (a.is_array()) {
    for (size_t k = 0; k < a.size(); ++k) {
      std::string d = FirstDifference(a[k], b[k], where + "[" + std::to_string(k) + "]");
      if (!d.empty()) return d;
    }
  } else if (a.is_object()) {
    for (const auto& [key, value] : a.items()) {
      const std::string at = where.empty() ? key : where + "." + key;
      if (!b.contains(key)) return at + ": not in the committed file";
      std::string d = FirstDifference(value, b[key], at);
      if (!d.empty()) return d;
    }
    for (const auto& [key, value] : b.items()) {
      if (!a.contains(key)) return (where.empty() ? key : where + "." + key) + ": missing";
    }
  }
  return "";
}

}  // namespace

std::string CompareManifestText(const std::string& regenerated, const std::string& committed) {
  nlohmann::json a = nlohmann::json::parse(regenerated, nullptr, false);
  nlohmann::json b = nlohmann::json::parse(committed, nullptr, false);
  if (b.is_discarded()) return "the committed file is not JSON";
  PATLAB_CHECK(!a.is_discarded());
  EraseRunAndPaths(&a);
  EraseRunAndPaths(&b);
  return FirstDifference(a, b, "");
}

std::string PaperMarkdown(const Reproduction& reproduction) {
  std::string md =
      "# The paper's numbers, reproduced\n\n"
      "Written by `patlab reproduce` (docs/reproduce.md); `patlab reproduce --check` fails when a "
      "verdict is not ok or a regenerated file differs. Rules: *within* |patlab - paper| <= "
      "tolerance; *below* / *above* patlab < / > the paper's bound (by the margin m where "
      "one is given: 4 standard errors); *explained* the paper's "
      "number differs for the stated reason and patlab must give the value the reason predicts; "
      "*reported* no check is possible, for the stated reason. Figs. 2, 3 and 6 print no "
      "numbers; `patlab reproduce` draws them (scripts/plot_track.py) and Fig. 5 "
      "(scripts/plot_fig5.py) from the regenerated CSVs.\n\n"
      "| where | quantity | paper | patlab | rule | tolerance or reason | verdict |\n"
      "|---|---|---|---|---|---|---|\n";
  const char* rule_names[] = {"within", "below", "above", "explained", "reported"};
  for (const PaperNumber& n : reproduction.numbers) {
    std::string rule = rule_names[static_cast<int>(n.rule)];
    // Appends, not operator+ chains: GCC 12 reports a false -Wrestrict on " " + std::string.
    if (n.rule == Rule::kWithin ||
        ((n.rule == Rule::kBelow || n.rule == Rule::kAbove) && n.tolerance > 0.0)) {
      rule.append(n.rule == Rule::kWithin ? " " : " by ").append(FormatSignificant(n.tolerance, 3));
    }
    if (n.rule == Rule::kExplained) {
      rule.append(" (expect ").append(FormatSignificant(n.expected, 6));
      if (n.tolerance > 0.0) rule.append(" within ").append(FormatSignificant(n.tolerance, 3));
      rule.append(")");
    }
    const char* verdict = n.rule == Rule::kReported ? "reported" : (n.ok ? "ok" : "FAILS");
    for (const std::string& cell :
         {n.where, n.quantity, FormatSignificant(n.paper, 4), FormatSignificant(n.patlab, 4), rule,
          n.reason, std::string(verdict)}) {
      md.append("| ").append(cell).append(" ");
    }
    md.append("|\n");
  }
  return md;
}

namespace {

// The pieces of a line of text between its commas (paper.md is Markdown, not CSV: a quote in it
// is text). A number in a piece of its own is compared within the tolerance.
std::vector<std::string_view> CommaPieces(std::string_view line) {
  std::vector<std::string_view> pieces;
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    pieces.push_back(line.substr(start, comma == std::string_view::npos ? comma : comma - start));
    if (comma == std::string_view::npos) return pieces;
    start = comma + 1;
  }
}

}  // namespace

std::string CompareResultText(const std::string& regenerated, const std::string& committed) {
  std::istringstream a(regenerated), b(committed);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ha = static_cast<bool>(std::getline(a, la));
    const bool hb = static_cast<bool>(std::getline(b, lb));
    if (!ha && !hb) return "";
    const std::string where = "line " + std::to_string(line) + ": ";
    if (ha != hb) return where + (ha ? "extra line " + la : "missing line " + lb);
    const auto ca = CommaPieces(la), cb = CommaPieces(lb);
    bool same = ca.size() == cb.size();
    for (size_t k = 0; same && k < ca.size(); ++k) {
      if (ca[k] == cb[k]) continue;
      const std::optional<double> x = io::ParseDouble(ca[k]), y = io::ParseDouble(cb[k]);
      same = x && y && std::abs(*x - *y) <= 2e-9 * std::max(std::abs(*x), std::abs(*y)) + 1e-12;
    }
    if (!same) return where + la + "; committed: " + lb;
  }
}

}  // namespace patlab::paper

// The paper checked number by number (docs/reproduce.md): `patlab reproduce` regenerates the
// result tables the paper's numbers are compared with (Fig. 5 with the KS and Wilcoxon columns:
// experiments/fig5.toml; Table I and its Wilcoxon tests, and the section-IV Butterfly:
// experiments/table1.toml; Table II: the ID counts of the shipped patterns), and lists every
// number the paper prints with patlab's value, the tolerance or the documented reason for a
// difference, and a verdict. `--check` fails when a number leaves its tolerance or a regenerated
// file differs from the committed one.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "patlab/paper/reproduce_compare.h"

namespace patlab::paper {

// How a paper number is judged.
enum class Rule {
  kWithin,     // |patlab - paper| <= tolerance
  kBelow,      // patlab < paper (the paper prints "p < 0.0001")
  kAbove,      // patlab > paper (the paper prints "no significant difference": p > 0.05)
  kExplained,  // the paper's number is wrong or not comparable, for the stated reason; patlab's
               // value must equal `expected` within `tolerance` (what the reason predicts)
  kReported,   // no check possible (the reason says why); patlab's value is shown
};

struct PaperNumber {
  std::string where;     // "Table I, 40 mm"
  std::string quantity;  // "sigma_x (mm)"
  double paper = 0.0;
  double patlab = 0.0;
  Rule rule = Rule::kWithin;
  double tolerance = 0.0;
  double expected = 0.0;  // kExplained only
  std::string reason;     // why this tolerance, or why the numbers differ
  bool ok = true;         // the verdict: the rule holds
};

// Every number, judged.
struct Reproduction {
  std::vector<PaperNumber> numbers;
  // The regenerated result files: path relative to the results directory -> content.
  std::vector<std::pair<std::string, std::string>> files;
  // How --check compares each regenerated CSV (reproduce_compare.h): every column's kind and,
  // for the Wilcoxon tests of Table I, each test's rank allowance from the regenerated samples.
  std::map<std::string, CsvRules> rules;
};

struct ReproduceOptions {
  std::string root = ".";           // the checkout: experiments/ and patterns/ are read from here
  int threads = 0;                  // 0 = all cores; results do not depend on it
  std::string out_dir = "results";  // where the files go
  // Called as the runs go (done, total), from the runners' own progress: the three runs (Fig. 5,
  // Table I, Table I without noise) count kProgressPerRun steps each; empty = no reports.
  std::function<void(int, int)> progress;
  static constexpr int kProgressPerRun = 100;
};

// Runs experiments/fig5.toml and experiments/table1.toml (twice: as calibrated, and without
// sensor noise or jitter for Fig. 6's quantisation panels) through the library (the same calls
// as `patlab simulate` and `patlab track`), counts the IDs of Table II, and judges every number.
// Reproduction::files: fig5.csv and .json; table1.csv, table1_tests.csv, track_errors.csv and
// table1.json; the same four under track_quantisation/ (errors decimated by 4, as
// scripts/regenerate_results.sh always made them); paper.md.
Reproduction Reproduce(const ReproduceOptions& options);

// A figure of the paper drawn from the regenerated CSVs by a plotting script (matplotlib): the
// command (argv[0] is /usr/bin/python3) and the PNG files it writes.
struct FigureStep {
  std::string figure;  // "Fig. 5"
  std::vector<std::string> argv;
  std::vector<std::string> outputs;
};
// Figs. 5 (scripts/plot_fig5.py) and 2, 3, 6 (scripts/plot_track.py), reading and writing
// options.out_dir. `patlab reproduce` runs them after writing the files.
std::vector<FigureStep> FigureSteps(const ReproduceOptions& options);

// The regenerated manifest (JSON) differs from the committed one: compared without the keys that
// describe the run (command line, threads, timings, rates, outputs) or where the inputs were
// read from (file paths), numbers within CompareResultText's tolerance. "" when they agree, else
// the first difference ("timings_s.wall ...").
std::string CompareManifestText(const std::string& regenerated, const std::string& committed);

// results/paper.md: a table of every number (paper, patlab, tolerance or reason, verdict).
std::string PaperMarkdown(const Reproduction& reproduction);

// A regenerated text file without column rules (paper.md) differs from the committed one: every
// cell (split at ',') equal as text, or both numbers with |a - b| <= 2e-9 max(|a|, |b|) + 1e-12.
// Returns "" when they agree, else the first differing line ("line 12: ... ; committed: ...").
// The CSVs are compared by CompareResultCsv with Reproduction::rules.
std::string CompareResultText(const std::string& regenerated, const std::string& committed);

}  // namespace patlab::paper

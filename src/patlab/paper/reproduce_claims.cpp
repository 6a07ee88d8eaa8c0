// The paper's numbers checked against the regenerated tables (reproduce_internal.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/csv.h"
#include "patlab/paper/reproduce_internal.h"

namespace patlab::paper {

namespace {

// A regenerated CSV with a lookup of a cell by the values of other cells in its row.
class Table {
 public:
  Table(const std::string& text, const std::string& name) : table_(io::ParseCsv(text, name, {})) {}
  // The number in `column` of the first row whose cells in `keys` (column -> value) all match.
  double Get(const std::map<std::string, std::string>& keys, const std::string& column) const {
    const std::optional<double> v = io::ParseDouble(Text(keys, column));
    PATLAB_CHECK(v.has_value());
    return *v;
  }
  std::string Text(const std::map<std::string, std::string>& keys,
                   const std::string& column) const {
    for (const io::CsvTable::Row& row : table_.rows) {
      bool match = true;
      for (const auto& [k, v] : keys) match = match && row.cells.at(Index(k)) == v;
      if (match) return row.cells.at(Index(column));
    }
    PATLAB_CHECK(false);
    return "";
  }

 private:
  size_t Index(const std::string& column) const {
    const std::optional<size_t> index = table_.Find(column);
    PATLAB_CHECK(index.has_value());
    return *index;
  }
  io::CsvTable table_;
};

PaperNumber Number(std::string where, std::string quantity, double paper, double patlab, Rule rule,
                   double tolerance, std::string reason) {
  PaperNumber n;
  n.where = std::move(where);
  n.quantity = std::move(quantity);
  n.paper = paper;
  n.patlab = patlab;
  n.rule = rule;
  n.tolerance = tolerance;
  n.reason = std::move(reason);
  return n;
}

PaperNumber Explained(std::string where, std::string quantity, double paper, double patlab,
                      double expected, std::string reason) {
  PaperNumber n = Number(std::move(where), std::move(quantity), paper, patlab, Rule::kExplained,
                         0.0, std::move(reason));
  n.expected = expected;
  return n;
}

void Judge(PaperNumber* n) {
  switch (n->rule) {
    case Rule::kWithin:
      n->ok = std::abs(n->patlab - n->paper) <= n->tolerance;
      break;
    case Rule::kBelow:  // with a margin (tolerance, e.g. 4 standard errors) when one is given
      n->ok = n->patlab + n->tolerance < n->paper;
      break;
    case Rule::kAbove:
      n->ok = n->patlab - n->tolerance > n->paper;
      break;
    case Rule::kExplained:
      n->ok = std::abs(n->patlab - n->expected) <= n->tolerance;
      break;
    case Rule::kReported:
      n->ok = true;
      break;
  }
}

// The standard error of a sample std from `dof` degrees of freedom (normal samples): s / sqrt(2
// dof). Fig. 5's std of one axis has n - 1, the pooled position std 2(n - 1).
double StdError(double s, double dof) { return s / std::sqrt(2.0 * dof); }

constexpr const char* kSimulatedCamera =
    "simulated camera: intensity noise and jitter (experiments/table1.toml) bring single patches "
    "near the paper's ~0.5 mm; it has no outliers or run-to-run variance, so per-size values are "
    "reported, not checked (paper-reproduction.md, Table I)";
constexpr const char* kFitted =
    "the simulated camera's noise was chosen to give the paper's overall ~0.5 mm: agreement to "
    "0.1 mm (20%) is what the fit promises";

// Table I: the six std and their intervals (reported), the overall level, the tests.
void TableOne(const Table& t, const Table& tests, std::vector<PaperNumber>* out) {
  const double paper[3][2][3] = {{{0.553, 0.546, 0.561}, {0.473, 0.467, 0.480}},
                                 {{0.543, 0.535, 0.550}, {0.504, 0.497, 0.511}},
                                 {{0.489, 0.482, 0.496}, {0.533, 0.526, 0.541}}};
  const char* sizes[] = {"40mm", "50mm", "60mm"};
  // The paper's intervals are iid chi-square ones: compared with the iid columns.
  const char* columns[2][3] = {{"est_sx_mm", "est_sx_iid_lo", "est_sx_iid_hi"},
                               {"est_sy_mm", "est_sy_iid_lo", "est_sy_iid_hi"}};
  const char* names[2][3] = {{"sigma_x (mm)", "sigma_x 95% CI low", "sigma_x 95% CI high"},
                             {"sigma_y (mm)", "sigma_y 95% CI low", "sigma_y 95% CI high"}};
  double sum_sq = 0.0;
  for (int s = 0; s < 3; ++s) {
    for (int a = 0; a < 2; ++a) {
      for (int k = 0; k < 3; ++k) {
        const double v = t.Get({{"subject", sizes[s]}}, columns[a][k]);
        if (k == 0) sum_sq += v * v;
        out->push_back(Number(std::string("Table I, ") + sizes[s], names[a][k], paper[s][a][k], v,
                              Rule::kReported, 0.0, kSimulatedCamera));
      }
    }
  }
  out->push_back(Number("Section II", "overall std, all sizes, x and y (mm)", 0.52,
                        std::sqrt(sum_sq / 6.0), Rule::kWithin, 0.1, kFitted));
  for (const char* other : {"40mm", "50mm"}) {
    const std::map<std::string, std::string> key = {
        {"error", "est"}, {"axis", "x"}, {"a", other}, {"b", "60mm"}};
    const bool sixty_smaller = tests.Text(key, "smaller") == "60mm";
    out->push_back(Number("Section II", std::string("Wilcoxon p, x: 60 mm < ") + other, 1e-4,
                          sixty_smaller ? tests.Get(key, "p_value") : 1.0, Rule::kBelow, 0.0,
                          "the paper's significant result along the travel (p < 0.0001), with "
                          "60 mm the smaller error"));
  }
  out->push_back(
      Number("Section II", "Wilcoxon p, y: 40 mm vs 60 mm", 1e-4,
             tests.Get({{"error", "est"}, {"axis", "y"}, {"a", "40mm"}, {"b", "60mm"}}, "p_value"),
             Rule::kReported, 0.0,
             "across the travel the paper's error grew with size; the simulation's "
             "does not (the smoothing estimate under-reads across the travel: "
             "paper-reproduction.md)"));
  out->push_back(
      Number("Section II", "Wilcoxon p, xy: 50 mm vs 40 mm", 0.02,
             tests.Get({{"error", "est"}, {"axis", "xy"}, {"a", "40mm"}, {"b", "50mm"}}, "p_value"),
             Rule::kReported, 0.0,
             "the paper calls p = 0.02 inconclusive; the simulation's 50 mm patch "
             "is not the worst"));
  out->push_back(Number("Section II", "samples per size (\"over 10,000\")", 10000,
                        t.Get({{"subject", "40mm"}}, "n"), Rule::kAbove, 0.0,
                        "the simulation keeps as many samples as the paper"));
}

// Table II: the ID counts with 2, 3, 4 colours (tolerance 10 mm, as `patlab ids`).
void TableTwo(const std::string& root, std::vector<PaperNumber>* out) {
  struct Row {
    const char* pattern;
    double paper[3];
  };
  const Row rows[] = {{"butterfly", {16, 64, 256}},
                      {"simple", {2, 3, 4}},
                      {"linear", {1, 3, 6}},
                      {"triangle", {2, 6, 12}}};
  for (const Row& r : rows) {
    const Pattern p = formats::LoadPatternFile(root + "/patterns/" + r.pattern + ".toml");
    const detect::Symmetry symmetry = detect::FindSymmetry(p, 10.0);
    for (int n = 2; n <= 4; ++n) {
      const auto count = static_cast<double>(detect::CountIds(p, symmetry, n));
      const std::string where = std::string("Table II, ") + r.pattern;
      const std::string quantity = std::to_string(n) + " colours";
      const double paper = r.paper[n - 2];
      if (std::string(r.pattern) == "butterfly" && n == 3) {
        out->push_back(Explained(where, quantity, paper, count, 81,
                                 "the paper's slip: n^4 IDs (3^4 = 81); its 64 = 4^3 comes from "
                                 "its formula 4^n, base and exponent swapped"));
      } else if (std::string(r.pattern) == "triangle" && n >= 3) {
        out->push_back(Explained(where, quantity, paper, count, n == 3 ? 8 : 20,
                                 "the paper counts only colourings with one odd patch, n(n-1); "
                                 "three different colours also fix the rotation: (n^3 - n)/3"));
      } else {
        out->push_back(Number(where, quantity, paper, count, Rule::kWithin, 0.0, "exact count"));
      }
    }
  }
}

// Fig. 5, the KS comparison and section IV's Butterfly.
void SectionFour(const sim::Experiment& fig5, const Table& f, const Table& t,
                 std::vector<PaperNumber>* out) {
  out->push_back(Number("Fig. 5", "simulated detections per data point", 100000,
                        static_cast<double>(fig5.trials), Rule::kWithin, 0.0, "the same count"));
  const std::map<std::string, std::string> simple = {
      {"pattern", "simple"}, {"estimator", "fast"}, {"sigma_mm", "1"}};
  const Pattern* found = nullptr;
  for (const Pattern& p : fig5.patterns) {
    if (p.name == "simple") found = &p;
  }
  PATLAB_CHECK(found != nullptr);
  const Pattern& sp = *found;
  const double d = (sp.patches[1].position_mm - sp.patches[0].position_mm).norm();
  const double s = f.Get(simple, "std_theta_rad");
  const double n = f.Get(simple, "trials");
  out->push_back(Number("Section III", "sigma_theta = sqrt(2 sigma^2)/d, Simple, sigma = 1 mm",
                        std::sqrt(2.0) / d, s, Rule::kWithin, 4.0 * s / std::sqrt(2.0 * (n - 1.0)),
                        "the paper's formula with patlab's d = " + FormatSignificant(d, 4) +
                            " mm; tolerance 4 standard errors of the simulated std"));
  // "works well when d > 10 sigma": the largest sigma of the sweep with d > 10 sigma.
  double largest = 0.0;
  for (const double sigma : fig5.sigmas_mm) {
    if (d > 10.0 * sigma) largest = std::max(largest, sigma);
  }
  const std::string at = FormatSignificant(largest, 6);
  const double s_large =
      f.Get({{"pattern", "simple"}, {"estimator", "fast"}, {"sigma_mm", at}}, "std_theta_rad");
  out->push_back(Number(
      "Section III",
      "sigma_theta = sqrt(2 sigma^2)/d, Simple, sigma = " + at + " mm (largest with d > 10 sigma)",
      std::sqrt(2.0) * largest / d, s_large, Rule::kWithin, 4.0 * StdError(s_large, n - 1.0),
      "\"works well when d > 10 sigma\"; tolerance 4 standard errors of the "
      "simulated std"));
  for (const char* axis : {"x", "y", "theta"}) {
    out->push_back(Number(
        "Section IV, KS", std::string("fast vs ML, Butterfly, sigma = 1 mm, ") + axis + ": p", 0.05,
        f.Get({{"pattern", "butterfly"}, {"estimator", "ml"}, {"sigma_mm", "1"}},
              std::string("ks_") + axis + "_p"),
        Rule::kAbove, 0.0,
        "\"no statistically significant differences\" after 100,000 samples: p > 0.05"));
  }
  // "at least for complicated patterns": the smallest KS p of ML vs fast over every sigma > 0 and
  // axis of the Butterfly and the Triangle.
  double smallest = 1.0;
  for (const char* pattern : {"butterfly", "triangle"}) {
    for (const double sigma : fig5.sigmas_mm) {
      if (sigma <= 0.0) continue;
      for (const char* axis : {"x", "y", "theta"}) {
        smallest = std::min(smallest, f.Get({{"pattern", pattern},
                                             {"estimator", "ml"},
                                             {"sigma_mm", FormatSignificant(sigma, 6)}},
                                            std::string("ks_") + axis + "_p"));
      }
    }
  }
  out->push_back(Number("Section IV, KS",
                        "fast vs ML, Butterfly and Triangle, every sigma > 0 and axis: smallest p",
                        0.05, smallest, Rule::kAbove, 0.0,
                        "\"no statistically significant differences\" for the complicated "
                        "patterns: every p > 0.05"));
  const char* fitted_butterfly = kFitted;
  const double bx = t.Get({{"subject", "butterfly"}}, "est_sx_mm");
  const double by = t.Get({{"subject", "butterfly"}}, "est_sy_mm");
  out->push_back(Number("Section IV, real Butterfly", "sigma_x (mm)", 0.3766, bx, Rule::kWithin,
                        0.1, fitted_butterfly));
  out->push_back(Number("Section IV, real Butterfly", "sigma_y (mm)", 0.3432, by, Rule::kWithin,
                        0.1, fitted_butterfly));
  out->push_back(Number("Section IV, real Butterfly", "sigma_theta (rad)", 0.0070,
                        t.Get({{"subject", "butterfly"}}, "est_stheta_rad"), Rule::kReported, 0.0,
                        "the simulated jitter translates the image and does not rotate the "
                        "pattern, so the simulated angle error is 2-3x below the paper's"));
  const double per_mm =
      f.Get({{"pattern", "butterfly"}, {"estimator", "ml"}, {"sigma_mm", "1"}}, "std_pos_mm");
  out->push_back(Number("Section IV, real Butterfly", "consistent patch sigma (mm)", 0.8,
                        (0.3766 + 0.3432) / 2.0 / per_mm, Rule::kWithin, 0.05,
                        "the paper's sigma_x, sigma_y over Fig. 5's Butterfly position std per mm "
                        "of patch sigma; \"around 0.8\" is one significant digit: +-0.05"));
}

// Section II's set-up: the paper's numbers that are inputs of experiments/table1.toml.
void SectionTwoSetup(const analysis::TrackOptions& o, std::vector<PaperNumber>* out) {
  const char* input = "an input of experiments/table1.toml, set to the paper's value";
  const auto add = [&](const char* quantity, double paper, double patlab, double tolerance,
                       const std::string& reason) {
    out->push_back(
        Number("Section II, set-up", quantity, paper, patlab, Rule::kWithin, tolerance, reason));
  };
  add("runs", 5, o.runs, 0.0, input);
  add("samples per run (\"about 2570\")", 2570, o.samples_per_run, 0.0, input);
  add("samples per second", 30, o.rate_hz, 0.0, input);
  add("platform speed (\"about 23 mm/sec\")", 23, o.speed_mm_per_s, 0.0, input);
  add("camera height (m)", 3, o.camera.height_mm / 1000.0, 0.0, input);
  add("smoothing kernel sigma (samples)", 10, o.smoothing_sigma_samples, 0.0, input);
  add("travel across the view (m)", 2, o.samples_per_run / o.rate_hz * o.speed_mm_per_s / 1000.0,
      0.05,
      "2570 samples at 23 mm/s and 30 Hz travel 1.97 m; the paper's \"2 meters\" rounded: "
      "within 0.05 m");
  const auto [lo, hi] = std::minmax_element(o.diameters_mm.begin(), o.diameters_mm.end());
  add("area of the largest patch / the smallest", 2.25, (*hi / *lo) * (*hi / *lo), 1e-12,
      "(60 / 40)^2 from the experiment's diameters: exact");
}

// Section II's "less than 5%" from best to worst combined error (sqrt(sx^2 + sy^2)).
void BestToWorst(const Table& t, std::vector<PaperNumber>* out) {
  double best = 1e300, worst = 0.0;
  std::string values;
  for (const char* size : {"40mm", "50mm", "60mm"}) {
    const double x = t.Get({{"subject", size}}, "est_sx_mm");
    const double y = t.Get({{"subject", size}}, "est_sy_mm");
    best = std::min(best, std::hypot(x, y));
    worst = std::max(worst, std::hypot(x, y));
    values.append(values.empty() ? "" : ", ").append(FormatFixed(std::hypot(x, y), 3));
  }
  std::string reason =
      "the paper's Table I gives 2.4%; the simulated camera's error falls with diameter more "
      "than the paper's camera's (combined error of 40, 50, 60 mm: ";
  reason.append(values).append(
      " mm), so its spread is wider; per-size values are not checked (paper-reproduction.md, "
      "Table I)");
  out->push_back(Number("Section II",
                        "best-to-worst difference of combined error (\"less than 5%\")", 0.05,
                        worst / best - 1.0, Rule::kReported, 0.0, reason));
}

// Fig. 5's claims about the patterns (section IV), at sigma = 1 mm, fast estimator, each with a
// margin of 4 standard errors.
void FigureFiveClaims(const sim::Experiment& fig5, const Table& f, std::vector<PaperNumber>* out) {
  const auto at = [&f](const char* pattern, const char* column) {
    return f.Get({{"pattern", pattern}, {"estimator", "fast"}, {"sigma_mm", "1"}}, column);
  };
  const double n = at("simple", "trials");
  // A ratio a/b of two independent stds and 4 standard errors of it (relative errors add in
  // quadrature).
  const auto ratio = [&](const char* a, const char* b, const char* column, double dof) {
    const double r = at(a, column) / at(b, column);
    return std::pair{r, 4.0 * r * std::sqrt(2.0) / std::sqrt(2.0 * dof)};
  };
  const char* order = "the paper's order in Fig. 5; ratio below 1 by 4 standard errors";
  for (const auto& [a, b] : {std::pair{"butterfly", "triangle"}, std::pair{"triangle", "linear"},
                             std::pair{"linear", "simple"}}) {
    const auto [rp, mp] = ratio(a, b, "std_pos_mm", 2.0 * (n - 1.0));
    out->push_back(Number("Section IV, Fig. 5", std::string("position std ") + a + " / " + b, 1.0,
                          rp, Rule::kBelow, mp, order));
    const auto [rt, mt] = ratio(a, b, "std_theta_rad", n - 1.0);
    out->push_back(Number("Section IV, Fig. 5", std::string("angle std ") + a + " / " + b, 1.0, rt,
                          Rule::kBelow, mt, order));
  }
  const auto distance = [&fig5](const char* name) {
    for (const Pattern& p : fig5.patterns) {
      if (p.name == name) {
        return (p.patches[p.orientation_pairs[0].to].position_mm -
                p.patches[p.orientation_pairs[0].from].position_mm)
            .norm();
      }
    }
    PATLAB_CHECK(false);
    return 0.0;
  };
  out->push_back(Number("Section IV, Fig. 5", "orientation pair: Linear's separation / Simple's",
                        2.0, distance("linear") / distance("simple"), Rule::kWithin, 1e-9,
                        "\"twice that of the Simple pattern\": the shipped patterns' geometry"));
  const auto [rt, mt] = ratio("simple", "linear", "std_theta_rad", n - 1.0);
  out->push_back(Number("Section IV, Fig. 5", "angle std Simple / Linear", 2.0, rt, Rule::kWithin,
                        mt,
                        "sigma_theta ~ sqrt(2) sigma / d with twice the d; 4 standard errors of "
                        "the ratio"));
  const double simple = at("simple", "std_pos_mm");
  PaperNumber one = Explained(
      "Section IV, Fig. 5", "Simple, fast: position std per mm of patch sigma", 1.0, simple,
      std::sqrt(0.75),
      "\"no better than a single patch\": across the pair the origin's error is the centroid's "
      "sigma/sqrt(2) and the lever 32.5 mm x sqrt(2) sigma / 65 mm, together one patch's sigma; "
      "along it sigma/sqrt(2); pooled per axis sqrt(3/4) sigma. 4 standard errors");
  one.tolerance = 4.0 * StdError(simple, 2.0 * (n - 1.0));
  out->push_back(one);
}

// "Not as low as predicted": the real Butterfly's error against Fig. 5's at the paper's single
// patch std of 0.52 mm, and its test against a single patch.
void RealButterflyClaims(const Table& f, const Table& t, std::vector<PaperNumber>* out) {
  const std::map<std::string, std::string> b1 = {
      {"pattern", "butterfly"}, {"estimator", "fast"}, {"sigma_mm", "1"}};
  const double predicted_theta = 0.52 * f.Get(b1, "std_theta_rad");
  const double predicted_pos = 0.52 * f.Get(b1, "std_pos_mm");
  out->push_back(Number("Section IV, real Butterfly",
                        "error above the simulation's prediction, theta (\"about 70%\")", 0.70,
                        0.0070 / predicted_theta - 1.0, Rule::kWithin, 0.05,
                        "the paper's sigma_theta = 0.0070 rad over Fig. 5's Butterfly at patch "
                        "sigma 0.52 mm (section II); \"about 70%\" is one significant digit: "
                        "+-0.05"));
  out->push_back(Number("Section IV, real Butterfly",
                        "error above the simulation's prediction, position", 0.70,
                        (0.3766 + 0.3432) / 2.0 / predicted_pos - 1.0, Rule::kReported, 0.0,
                        "the same ratio for the paper's sigma_x, sigma_y is 54%: the paper's "
                        "\"about 70%\" matches its angle error, not its position error"));
  // One-sided z test of log(std ratio) (normal samples: var(log s) = 1 / (2(n - 1))). Successive
  // samples are correlated (Fig. 6), so n overstates the information; p is far below the bound
  // even for n / 100.
  const double sb = t.Get({{"subject", "butterfly"}}, "est_sx_mm");
  const double sp = t.Get({{"subject", "40mm"}}, "est_sx_mm");
  const double nb = t.Get({{"subject", "butterfly"}}, "n");
  const double np = t.Get({{"subject", "40mm"}}, "n");
  const double z = std::log(sb / sp) / std::sqrt(0.5 / (nb - 1.0) + 0.5 / (np - 1.0));
  out->push_back(Number("Section IV, real Butterfly", "better than a single patch: p, x", 1e-4,
                        0.5 * std::erfc(-z / std::sqrt(2.0)), Rule::kBelow, 0.0,
                        "simulated Butterfly vs 40 mm patch along the travel: one-sided z test "
                        "of the log std ratio (p < 0.0001 in the paper)"));
}

}  // namespace

void AddPaperNumbers(const ReproduceOptions& options, const sim::Experiment& fig5,
                     const analysis::TrackOptions& table1, const RegeneratedTables& tables,
                     std::vector<PaperNumber>* out) {
  const Table f(tables.fig5_csv, "fig5.csv"), t(tables.table1_csv, "table1.csv"),
      tests(tables.tests_csv, "table1_tests.csv");
  TableOne(t, tests, out);
  BestToWorst(t, out);
  SectionTwoSetup(table1, out);
  TableTwo(options.root, out);
  SectionFour(fig5, f, t, out);
  FigureFiveClaims(fig5, f, out);
  RealButterflyClaims(f, t, out);
  for (PaperNumber& n : *out) Judge(&n);
}

}  // namespace patlab::paper

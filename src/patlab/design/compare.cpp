#include "patlab/design/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/codebook.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/io/csv.h"
#include "patlab/stats/intervals.h"
#include "patlab/stats/noncentral_chi2.h"

namespace patlab::design {

namespace {

using nlohmann::ordered_json;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// The wrong rotation passes the detector's test in 1 of 1000 fits at the onset.
constexpr double kOnsetP = 0.001;
// ML against fast: 5 tests (KS x, y, theta; Wilcoxon position, theta) at a family-wise 5%
// (Bonferroni): each p below 0.01 counts as a difference.
constexpr double kTestAlpha = 0.01;

std::string SigmaText(double sigma_mm) { return FormatNumber(sigma_mm) + "mm"; }

}  // namespace

// The detector's stage-4 tolerance E_max / patch_sigma^2 for this pattern with every patch:
// chi2_{2m-3}^-1(geometry_confidence), read from a detector so the two cannot drift apart.
double DetectorChiSquared(const Pattern& pattern, double tolerance_mm) {
  std::vector<std::string> palette = {"blue", kEvaluateIdColours[0]};
  for (const Patch& patch : pattern.patches) {
    if (patch.role == PatchRole::kFixed &&
        std::find(palette.begin(), palette.end(), patch.colour) == palette.end()) {
      palette.push_back(patch.colour);
    }
  }
  detect::DetectorOptions options;
  options.patch_sigma_mm = 1.0;
  const detect::Detector detector(detect::MakeDetectorConfig(
      palette, options,
      {formats::MakeDetectorPattern(pattern, {"blue"}, "", {kEvaluateIdColours[0]},
                                    tolerance_mm)}));
  return detector.ResidualTolerance(0);
}

// Noise-free E of the rigid fit (translation and rotation, key included; detector stage 4) of the
// pattern to itself with circular position j matched to j + shift.
double WrongRotationError(const Pattern& pattern, const detect::Symmetry& symmetry, int shift) {
  const int m = static_cast<int>(symmetry.circular_order.size());
  Vec2 centroid = Vec2::Zero();
  for (const Patch& patch : pattern.patches) centroid += patch.position_mm;
  centroid /= pattern.size();
  const Vec2 key = pattern.patches[pattern.key_index].position_mm - centroid;
  double sq = 2.0 * key.squaredNorm(), a = key.squaredNorm(), b = 0.0;
  for (int j = 0; j < m; ++j) {
    const Vec2 p = pattern.patches[symmetry.circular_order[j]].position_mm - centroid;
    const Vec2 q = pattern.patches[symmetry.circular_order[(j + shift) % m]].position_mm - centroid;
    sq += p.squaredNorm() + q.squaredNorm();
    a += p.dot(q);
    b += p.x() * q.y() - p.y() * q.x();
  }
  // 2-D Procrustes (Umeyama 1991): E = sum|p|^2 + sum|q|^2 - 2 sqrt(A^2 + B^2).
  return std::max(0.0, sq - 2.0 * std::sqrt(a * a + b * b));
}

// The sigma at which the wrong rotation's rigid-fit error E passes the detector's test
// E <= chi2 sigma^2 in kOnsetP of the fits: E / sigma^2 is noncentral chi-square with dof degrees
// of freedom and noncentrality E0 / sigma^2 (see DesignGeometry), so sigma = sqrt(E0 / lambda*)
// with lambda* the noncentrality at which P(chi'^2(dof, lambda*) <= chi2) = kOnsetP. lambda*
// depends on (dof, chi2) alone: the last one is kept, since the layout search asks for it with
// the same pair for every layout.
double RotationOnsetSigma(double e0, int dof, double chi2) {
  thread_local double last_dof = -1.0, last_chi2 = -1.0, last_lambda = 0.0;
  if (static_cast<double>(dof) != last_dof || chi2 != last_chi2) {
    last_lambda = stats::NoncentralityForCdf(dof, chi2, kOnsetP);
    last_dof = dof;
    last_chi2 = chi2;
  }
  return std::sqrt(e0 / last_lambda);
}

namespace {

void CheckDesigns(const std::vector<std::pair<Pattern, std::string>>& designs) {
  if (designs.empty()) throw InputError("no designs; expected at least one pattern file");
  for (size_t d = 0; d < designs.size(); ++d) {
    const auto& [pattern, file] = designs[d];
    if (detect::IdSlots(pattern).empty()) {
      throw InputError(file + ": design " + pattern.name +
                       " has no ID slots; expected at least one patch with role = \"id\"");
    }
    for (size_t e = 0; e < d; ++e) {
      if (designs[e].first.name == pattern.name) {
        throw InputError(file + ": design name \"" + pattern.name + "\" is also the name in " +
                         designs[e].second + "; expected distinct design names");
      }
    }
  }
}

// Column names that depend on the options.
std::string IdsColumn(int n) { return "ids_" + std::to_string(n) + "c"; }
std::string WrongIdColumn(double s) { return "wrong_id_" + SigmaText(s); }
std::string AmbiguousColumn(double s) { return "ambiguous_" + SigmaText(s); }
std::string DetectionColumn(double s) { return "detection_" + SigmaText(s); }
std::string RotationErrorsColumn(double s) { return "rotation_errors_" + SigmaText(s); }

}  // namespace

std::vector<CompareColumn> CompareColumns(const EvaluateOptions& o) {
  std::vector<CompareColumn> c = {
      {"diameter_mm", false, "outer diameter about the pose point, mm"},
      {"min_gap_mm", true, "smallest edge-to-edge gap between patches, mm"},
      {"rotations", false, "rotations ID colours must decide (effective symmetry group order)"},
      {"crlb_pos_per_mm", false, "Cramer-Rao bound on position std per axis, mm per mm of sigma"},
      {"fast_pos_per_mm", false, "fast estimator position std per axis (Monte-Carlo) / sigma"},
      {"ml_pos_per_mm", false, "ML estimator position std per axis (Monte-Carlo) / sigma"},
      {"crlb_theta_mrad_per_mm", false, "Cramer-Rao bound on angle std, mrad per mm of sigma"},
      {"fast_theta_mrad_per_mm", false, "fast estimator angle std (Monte-Carlo) / sigma, mrad/mm"},
      {"ml_theta_mrad_per_mm", false, "ML estimator angle std (Monte-Carlo) / sigma, mrad/mm"},
      {"fast_eff_pos", true, "fast position efficiency: CRLB^2 / achieved^2"},
      {"fast_eff_theta", true, "fast angle efficiency: CRLB^2 / achieved^2"},
  };
  for (int n : o.colour_counts) {
    c.push_back({IdsColumn(n), true, "IDs with " + std::to_string(n) + " ID colours"});
  }
  c.push_back({"rotation_sigma0_mm", true,
               "patch sigma at which the detector's tolerance reaches that rotation, no noise"});
  c.push_back({"rotation_onset_mm", true,
               "patch sigma at which noise lets that rotation pass in 1 of 1000 fits"});
  for (double s : o.sigmas_mm) {
    c.push_back({DetectionColumn(s), true, "correct detections / robots at " + SigmaText(s)});
    c.push_back({WrongIdColumn(s), false, "wrong ID / (correct + wrong) at " + SigmaText(s)});
    c.push_back({AmbiguousColumn(s), false, "ambiguous / robots at " + SigmaText(s)});
    c.push_back(
        {RotationErrorsColumn(s), false, "(wrong ID + ambiguous) / robots at " + SigmaText(s)});
  }
  return c;
}

std::vector<OptionsProblem> Check(const CompareOptions& options) {
  std::vector<OptionsProblem> problems = Check(options.evaluate);
  const std::vector<CompareColumn> columns = CompareColumns(options.evaluate);
  std::string names;
  bool known = false;
  for (const CompareColumn& c : columns) {
    if (!names.empty()) names += ", ";
    names += c.name;
    known = known || c.name == options.sort_by;
  }
  OptionsChecker check;
  if (!known) {
    check.Fail("--sort-by", "--sort-by is \"" + options.sort_by + "\"; expected one of: " + names);
  }
  for (OptionsProblem& p : check.Take()) problems.push_back(std::move(p));
  return problems;
}

void Validate(const CompareOptions& options) { ThrowFirstProblem(Check(options)); }

DesignGeometry ComputeDesignGeometry(const Pattern& pattern, const detect::Symmetry& symmetry) {
  DesignGeometry g;
  g.min_gap_mm = kInf;
  for (int i = 0; i < pattern.size(); ++i) {
    const Patch& p = pattern.patches[i];
    g.outer_diameter_mm =
        std::max(g.outer_diameter_mm, 2.0 * (p.position_mm.norm() + p.BoundingRadius()));
    for (int j = 0; j < i; ++j) {
      g.min_gap_mm = std::min(g.min_gap_mm, PatchGap(p, pattern.patches[j]));
    }
  }
  g.wrong_rotation_e0_mm2 = kInf;
  for (const detect::ShiftFit& fit : symmetry.fits) {
    const bool decided_by_colours =
        std::find(symmetry.effective_shifts.begin(), symmetry.effective_shifts.end(), fit.shift) !=
            symmetry.effective_shifts.end() ||
        !fit.preserves_roles;
    if (decided_by_colours) continue;
    g.wrong_rotation_e0_mm2 =
        std::min(g.wrong_rotation_e0_mm2, WrongRotationError(pattern, symmetry, fit.shift));
  }
  g.chi2_quantile = DetectorChiSquared(pattern, symmetry.tolerance_mm);
  if (std::isinf(g.wrong_rotation_e0_mm2)) {
    g.rotation_sigma0_mm = g.rotation_onset_mm = kNan;
    return g;
  }
  g.rotation_sigma0_mm = std::sqrt(g.wrong_rotation_e0_mm2 / g.chi2_quantile);
  g.rotation_onset_mm =
      RotationOnsetSigma(g.wrong_rotation_e0_mm2, 2 * pattern.size() - 3, g.chi2_quantile);
  return g;
}

namespace {

const sim::EstimatorResult* FindEstimator(const EvaluationReport& r, estimate::Estimator est) {
  for (const sim::EstimatorResult& e : r.monte_carlo.points.at(0).estimators) {
    if (e.estimator == est) return &e;
  }
  return nullptr;
}

std::string Verdict(const sim::EstimatorResult& ml) {
  const sim::Comparison& c = ml.vs_fast;
  if (!c.computed) return "not computed";
  std::string differ;
  const std::pair<const char*, double> tests[] = {{"ks_x", c.ks_x.p_value},
                                                  {"ks_y", c.ks_y.p_value},
                                                  {"ks_theta", c.ks_theta.p_value},
                                                  {"wilcoxon_pos", c.wilcoxon_position.p_value},
                                                  {"wilcoxon_theta", c.wilcoxon_theta.p_value}};
  for (const auto& [name, p] : tests) {
    if (p < kTestAlpha) {
      if (!differ.empty()) differ += ' ';
      differ += name;
    }
  }
  return differ.empty() ? "same" : "differ: " + differ;
}

// Part 2's cells: std / sigma with its 95% interval, per estimator.
void MonteCarloCells(const EvaluationReport& r, const sim::EstimatorResult& e,
                     const std::string& name, std::vector<std::pair<std::string, double>>* c) {
  const double sigma = r.options.sigma_mm;
  c->push_back({name + "_pos_per_mm", e.position_std_mm / sigma});
  c->push_back({name + "_pos_per_mm_lo", e.position_std_lower_mm / sigma});
  c->push_back({name + "_pos_per_mm_hi", e.position_std_upper_mm / sigma});
  c->push_back({name + "_theta_mrad_per_mm", 1e3 * e.theta.std / sigma});
  c->push_back({name + "_theta_mrad_per_mm_lo", 1e3 * e.theta.std_lower / sigma});
  c->push_back({name + "_theta_mrad_per_mm_hi", 1e3 * e.theta.std_upper / sigma});
}

void RateCells(const std::string& name, const stats::Proportion* p,
               std::vector<std::pair<std::string, double>>* c) {
  c->push_back({name, p ? p->rate : kNan});
  c->push_back({name + "_lo", p ? p->lower : kNan});
  c->push_back({name + "_hi", p ? p->upper : kNan});
}

// Every cell of a row: the rankable columns of CompareColumns and, after each, its interval.
void FillCells(CompareRow* row) {
  const EvaluationReport& r = row->report;
  const sim::EstimatorResult* fast = FindEstimator(r, estimate::Estimator::kFast);
  const sim::EstimatorResult* ml = FindEstimator(r, estimate::Estimator::kMl);
  PATLAB_CHECK(fast != nullptr && ml != nullptr);
  auto& c = row->cells;
  const DesignGeometry& g = row->geometry;
  c = {{"diameter_mm", g.outer_diameter_mm},
       {"min_gap_mm", g.min_gap_mm},
       {"rotations", r.ids.symmetry.effective_order()},
       {"crlb_pos_per_mm", r.crlb.position_per_axis},
       {"crlb_theta_mrad_per_mm", 1e3 * r.crlb.theta}};
  MonteCarloCells(r, *fast, "fast", &c);
  MonteCarloCells(r, *ml, "ml", &c);
  c.push_back({"fast_eff_pos", sim::Efficiency(fast->crlb_position_mm, fast->position_std_mm)});
  c.push_back({"fast_eff_theta", sim::Efficiency(fast->crlb_theta_rad, fast->theta.std)});
  for (const auto& [n, ids] : r.ids.counts) c.push_back({IdsColumn(n), static_cast<double>(ids)});
  c.push_back({"rotation_sigma0_mm", g.rotation_sigma0_mm});
  c.push_back({"rotation_onset_mm", g.rotation_onset_mm});
  const Misidentification& m = r.misidentification;
  c.push_back({"codebook_ids", m.ids});
  for (size_t k = 0; k < r.options.sigmas_mm.size(); ++k) {
    const double s = r.options.sigmas_mm[k];
    const sim::DetectPointResult* d = m.run ? &m.result.points.at(k) : nullptr;
    RateCells(DetectionColumn(s), d ? &d->detection : nullptr, &c);
    RateCells(WrongIdColumn(s), d ? &d->wrong_id_rate : nullptr, &c);
    RateCells(AmbiguousColumn(s), d ? &d->ambiguous_rate : nullptr, &c);
    const stats::Proportion errors =
        d ? stats::WilsonInterval(d->wrong_id + d->ambiguous, d->robots) : stats::Proportion{};
    RateCells(RotationErrorsColumn(s), d ? &errors : nullptr, &c);
  }
  const sim::Comparison& vs = ml->vs_fast;
  c.push_back({"ks_x_p", vs.computed ? vs.ks_x.p_value : kNan});
  c.push_back({"ks_y_p", vs.computed ? vs.ks_y.p_value : kNan});
  c.push_back({"ks_theta_p", vs.computed ? vs.ks_theta.p_value : kNan});
  c.push_back({"wilcoxon_pos_p", vs.computed ? vs.wilcoxon_position.p_value : kNan});
  c.push_back({"wilcoxon_theta_p", vs.computed ? vs.wilcoxon_theta.p_value : kNan});
  row->verdict = Verdict(*ml);
}

double Cell(const CompareRow& row, const std::string& name) {
  for (const auto& [n, v] : row.cells) {
    if (n == name) return v;
  }
  PATLAB_CHECK(false);
  return kNan;
}

void Rank(const CompareOptions& o, const std::vector<CompareColumn>& columns,
          std::vector<CompareRow>* rows) {
  const auto col = std::find_if(columns.begin(), columns.end(),
                                [&](const CompareColumn& c) { return c.name == o.sort_by; });
  PATLAB_CHECK(col != columns.end());
  const bool larger = col->larger_is_better;
  // NaN (not applicable) ranks last; infinity is a value (e.g. no wrong rotation to reject).
  std::stable_sort(rows->begin(), rows->end(), [&](const CompareRow& a, const CompareRow& b) {
    const double va = Cell(a, o.sort_by), vb = Cell(b, o.sort_by);
    if (std::isnan(va) || std::isnan(vb)) return !std::isnan(va) && std::isnan(vb);
    return larger ? va > vb : va < vb;
  });
  for (size_t k = 0; k < rows->size(); ++k) (*rows)[k].rank = static_cast<int>(k) + 1;
}

}  // namespace

CompareResult CompareDesigns(const std::vector<std::pair<Pattern, std::string>>& designs,
                             const CompareOptions& options) {
  Validate(options);
  CheckDesigns(designs);
  const auto start = std::chrono::steady_clock::now();
  CompareResult result;
  result.options = options;
  result.options.progress = nullptr;
  result.columns = CompareColumns(options.evaluate);
  const int units_per_design = 1 + static_cast<int>(options.evaluate.sigmas_mm.size());
  const int units = units_per_design * static_cast<int>(designs.size());
  for (size_t d = 0; d < designs.size(); ++d) {
    const auto& [pattern, file] = designs[d];
    EvaluateOptions eo = options.evaluate;
    const int base = static_cast<int>(d) * units_per_design;
    if (options.progress) {
      eo.progress = [&, base](int done, int /*total*/) { options.progress(base + done, units); };
    }
    // Built in place: a local CompareRow moved into the vector trips GCC 12's false
    // -Wmaybe-uninitialized on EvaluateOptions' initializer lists.
    CompareRow& row = result.rows.emplace_back();
    row.design = pattern.name;
    row.file = file;
    row.patches = pattern.size();
    row.id_slots = static_cast<int>(detect::IdSlots(pattern).size());
    row.report = EvaluatePattern(pattern, file, eo);
    row.report.options.progress = nullptr;
    row.geometry = ComputeDesignGeometry(pattern, row.report.ids.symmetry);
    FillCells(&row);
    if (options.progress) options.progress(base + units_per_design, units);
  }
  Rank(options, result.columns, &result.rows);
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

namespace {

std::string Fixed(double v, int decimals) {
  return std::isnan(v) ? "-" : std::isinf(v) ? "inf" : FormatFixed(v, decimals);
}

std::string RateText(const CompareRow& row, const std::string& name) {
  const double v = Cell(row, name);
  if (std::isnan(v)) return "not run";
  return StringPrintf("%.4f [%.4f, %.4f]", v, Cell(row, name + "_lo"), Cell(row, name + "_hi"));
}

std::string RankedTableText(const CompareResult& result) {
  const EvaluateOptions& o = result.options.evaluate;
  std::string ids_header;
  for (int n : o.colour_counts) {
    if (!ids_header.empty()) ids_header += '/';
    ids_header += std::to_string(n);
  }
  std::string out = StringPrintf(
      "%-4s  %-20s  %-8s  %-6s  %-12s  %-4s  %-21s  %-21s  %-11s  %-13s  %s\n", "rank", "design",
      "diam mm", "gap mm", ("IDs " + ids_header + "c").c_str(), "rot", "pos CRLB/fast/ML",
      "angle CRLB/fast/ML", "fast eff", "rot sigma0/on", "ML vs fast");
  for (const CompareRow& row : result.rows) {
    std::string ids;
    for (int n : o.colour_counts) {
      if (!ids.empty()) ids += '/';
      ids += FormatNumber(Cell(row, IdsColumn(n)));
    }
    const std::string pos = Fixed(Cell(row, "crlb_pos_per_mm"), 3) + "/" +
                            Fixed(Cell(row, "fast_pos_per_mm"), 3) + "/" +
                            Fixed(Cell(row, "ml_pos_per_mm"), 3);
    const std::string angle = Fixed(Cell(row, "crlb_theta_mrad_per_mm"), 2) + "/" +
                              Fixed(Cell(row, "fast_theta_mrad_per_mm"), 2) + "/" +
                              Fixed(Cell(row, "ml_theta_mrad_per_mm"), 2);
    const std::string eff =
        Fixed(Cell(row, "fast_eff_pos"), 3) + "/" + Fixed(Cell(row, "fast_eff_theta"), 3);
    const std::string rot =
        Fixed(Cell(row, "rotation_sigma0_mm"), 2) + "/" + Fixed(Cell(row, "rotation_onset_mm"), 2);
    out += StringPrintf("%-4d  %-20s  %-8s  %-6s  %-12s  %-4d  %-21s  %-21s  %-11s  %-13s  %s\n",
                        row.rank, row.design.c_str(), Fixed(Cell(row, "diameter_mm"), 1).c_str(),
                        Fixed(Cell(row, "min_gap_mm"), 1).c_str(), ids.c_str(),
                        static_cast<int>(Cell(row, "rotations")), pos.c_str(), angle.c_str(),
                        eff.c_str(), rot.c_str(), row.verdict.c_str());
  }
  return out;
}

std::string MisidentificationTableText(const CompareResult& result) {
  const EvaluateOptions& o = result.options.evaluate;
  std::string out;
  for (double s : o.sigmas_mm) {
    out += "\nsigma " + SigmaText(s) + " (" + std::to_string(o.frames) +
           " frames, up to 10 robots each)\n";
    out += StringPrintf("%-4s  %-20s  %-4s  %-24s  %-24s  %s\n", "rank", "design", "IDs",
                        "detection [95%]", "wrong ID [95%]", "ambiguous [95%]");
    for (const CompareRow& row : result.rows) {
      out += StringPrintf("%-4d  %-20s  %-4s  %-24s  %-24s  %s\n", row.rank, row.design.c_str(),
                          FormatNumber(Cell(row, "codebook_ids")).c_str(),
                          RateText(row, DetectionColumn(s)).c_str(),
                          RateText(row, WrongIdColumn(s)).c_str(),
                          RateText(row, AmbiguousColumn(s)).c_str());
    }
  }
  return out;
}

}  // namespace

std::string CompareText(const CompareResult& result) {
  const CompareOptions& co = result.options;
  const EvaluateOptions& o = co.evaluate;
  std::string out = "Designs ranked by " + co.sort_by +
                    " (best first). Monte-Carlo at sigma = " + FormatNumber(o.sigma_mm) + " mm, " +
                    std::to_string(o.trials) +
                    " trials; stds per mm of patch sigma (position mm/mm per axis, angle "
                    "mrad/mm); symmetry tolerance " +
                    FormatNumber(o.tolerance_mm) + " mm; seed " + std::to_string(o.seed) + "\n\n";
  out += RankedTableText(result);
  out +=
      "\nrot: rotations ID colours must decide; fast eff: CRLB^2/achieved^2 (position/angle); "
      "rot sigma0/on: patch sigma (mm) at which a wrong rotation geometry must reject reaches "
      "the detector's tolerance without noise / passes in 1 of 1000 fits with noise (- : colours "
      "decide every rotation); ML vs fast: KS (x, y, theta) and Wilcoxon (|position|, |theta|) "
      "at p < 0.01 each\n";
  out +=
      "\nMisidentification in whole frames (detect-mode Monte-Carlo, 95% Wilson intervals; "
      "codebook: <design>.codebook.toml next to the file, else ";
  out += o.id_colours ? std::to_string(*o.id_colours) : std::string("2");
  out += " ID colours)\n";
  return out + MisidentificationTableText(result);
}

std::string CompareCsv(const CompareResult& result) {
  std::vector<std::string> header = {"rank", "design", "file", "patches", "id_slots"};
  if (!result.rows.empty()) {
    for (const auto& [name, value] : result.rows.front().cells) header.push_back(name);
  }
  header.emplace_back("verdict");
  std::vector<std::vector<std::string>> lines = {header};
  for (const CompareRow& row : result.rows) {
    std::vector<std::string> cells = {std::to_string(row.rank), row.design, row.file,
                                      std::to_string(row.patches), std::to_string(row.id_slots)};
    for (const auto& [name, value] : row.cells) cells.push_back(FormatSignificant(value, 6));
    cells.push_back(row.verdict);
    lines.push_back(std::move(cells));
  }
  std::string out;
  for (const std::vector<std::string>& line : lines) out += io::CsvRow(line);
  return out;
}

std::string CompareJson(const CompareResult& result) {
  const EvaluateOptions& o = result.options.evaluate;
  ordered_json j;
  j["tool"] = "patlab compare";
  j["version"] = PATLAB_VERSION;
  j["options"] = {{"sort_by", result.options.sort_by},
                  {"sigma_mm", o.sigma_mm},
                  {"trials", o.trials},
                  {"colour_counts", o.colour_counts},
                  {"tolerance_mm", o.tolerance_mm},
                  {"sigmas_mm", o.sigmas_mm},
                  {"frames", o.frames},
                  {"seed", o.seed}};
  for (const CompareColumn& c : result.columns) {
    j["columns"].push_back(
        {{"name", c.name}, {"larger_is_better", c.larger_is_better}, {"meaning", c.meaning}});
  }
  j["rows"] = ordered_json::array();
  for (const CompareRow& row : result.rows) {
    ordered_json cells = ordered_json::object();
    for (const auto& [name, value] : row.cells) cells[name] = value;  // NaN and inf -> null
    j["rows"].push_back({{"rank", row.rank},
                         {"design", row.design},
                         {"file", row.file},
                         {"patches", row.patches},
                         {"id_slots", row.id_slots},
                         {"symmetry", detect::SymmetrySummary(row.report.ids.symmetry)},
                         {"cells", cells},
                         {"verdict", row.verdict}});
  }
  return j.dump(2) + "\n";
}

}  // namespace patlab::design

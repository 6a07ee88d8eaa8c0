// Ranking pattern designs side by side (behind `patlab compare`): every design runs the same work
// as `patlab evaluate` (same options, same seed, so a design's numbers do not depend on which
// others it is compared with), and one row per design gathers size, accuracy against the
// Cramer-Rao bound, ID capacity under the symmetry rule of detect/codebook.h, how robust the
// rotation fix is, misidentification in whole frames, and the KS / Wilcoxon verdict of ML
// against fast. docs/compare.md defines every column.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/design/evaluate.h"

namespace patlab::design {

struct CompareOptions {
  EvaluateOptions evaluate;  // the work per design (parts 1-4 of patlab evaluate)
  // The column the designs are ranked by (a name of CompareColumns() with a direction), best
  // first; ties keep the order the designs were given in.
  std::string sort_by = "fast_theta_mrad_per_mm";
  // Called on the calling thread after each unit of work (one Monte-Carlo point or one
  // detect-mode sigma of one design): (units done, units in all).
  std::function<void(int, int)> progress;
};
// sort_by one of the column names with a direction; the evaluate options as Check(Evaluate...).
std::vector<OptionsProblem> Check(const CompareOptions& options);
void Validate(const CompareOptions& options);

// A column that can rank designs: its name, whether larger is better, and what it means.
struct CompareColumn {
  std::string name;
  bool larger_is_better = false;
  std::string meaning;
};
// The rankable columns for these options (the per-palette and per-sigma columns depend on them).
std::vector<CompareColumn> CompareColumns(const EvaluateOptions& options);

// Geometry of one design that needs no simulation.
struct DesignGeometry {
  // Diameter (mm) of the smallest circle about the pattern origin (the pose point) that holds
  // every patch: 2 max |p_i| + r_i.
  double outer_diameter_mm = 0.0;
  // Smallest edge-to-edge distance (mm) between two patches: min |p_i - p_j| - r_i - r_j.
  double min_gap_mm = 0.0;
  // The rotation fix: E0 (mm^2) is the smallest noise-free rigid-fit error (detector stage 4,
  // key included) of a wrong rotation that neither ID colours nor fixed colours decide, i.e. a
  // shift outside the effective symmetry group; infinite when every wrong rotation is decided
  // by colours (then geometry has nothing to fix).
  double wrong_rotation_e0_mm2 = 0.0;
  // sqrt(E0) / patch sigma at which the detector (patch_sigma_mm = sigma, confidence 0.9999)
  // still rejects that rotation without noise: sqrt(chi2_{2m-3}^-1(0.9999)); the margin of the
  // design in units of patch sigma is sqrt(E0) / sigma against this.
  double chi2_quantile = 0.0;
  // sigma0 = sqrt(E0 / chi2): the patch sigma (mm) at which the detector's tolerance reaches the
  // wrong rotation without noise.
  double rotation_sigma0_mm = 0.0;
  // The onset with noise: the rigid-fit error E of the wrong rotation, over sigma^2, is
  // noncentral chi-square with 2m - 3 degrees of freedom and noncentrality E0 / sigma^2 (exact
  // for isotropic Gaussian patch noise and a rigid fit linear in the noise); the onset is the
  // sigma at which it passes the test, E <= chi2 sigma^2, in 1 of 1000 fits
  // (stats/noncentral_chi2.h). The first-order normal approximation used before put it 7-11%
  // lower. Validated against detect-mode frames in docs/compare.md.
  double rotation_onset_mm = 0.0;
};
DesignGeometry ComputeDesignGeometry(const Pattern& pattern, const detect::Symmetry& symmetry);

// The pieces of the rotation fix above, for callers that evaluate many layouts of one size (the
// layout search of design/design.h): the noise-free E (mm^2) of circular position j matched to
// j + shift; the detector's chi2_{2m-3}^-1(0.9999) for the pattern (builds a detector: call it
// once per pattern size); the onset sigma (mm) from E0, dof = 2m - 3 and that quantile (exact
// noncentral chi-square, as DesignGeometry::rotation_onset_mm).
double WrongRotationError(const Pattern& pattern, const detect::Symmetry& symmetry, int shift);
double DetectorChiSquared(const Pattern& pattern, double tolerance_mm);
double RotationOnsetSigma(double e0_mm2, int dof, double chi2);

struct CompareRow {
  std::string design;  // pattern name
  std::string file;
  int patches = 0, id_slots = 0;
  DesignGeometry geometry;
  EvaluationReport report;  // parts 1-4 as patlab evaluate
  // Cells by column name (numbers; NaN when not applicable), for sorting and the outputs.
  std::vector<std::pair<std::string, double>> cells;
  std::string verdict;  // KS / Wilcoxon of ML against fast: "same" or "differ (<which>)"
  int rank = 0;         // 1 = best by options.sort_by
};

struct CompareResult {
  CompareOptions options;
  std::vector<CompareColumn> columns;
  std::vector<CompareRow> rows;  // ranked
  double wall_seconds = 0.0;
};

// Compares the designs (pattern, file). Throws InputError naming the file for a design with no ID
// slots (nothing to identify) or two designs with the same name.
CompareResult CompareDesigns(const std::vector<std::pair<Pattern, std::string>>& designs,
                             const CompareOptions& options);

// The ranked table for people, CSV (one row per design, every column, with 95% intervals), and
// JSON (options, columns with their meaning, rows).
std::string CompareText(const CompareResult& result);
std::string CompareCsv(const CompareResult& result);
std::string CompareJson(const CompareResult& result);

}  // namespace patlab::design

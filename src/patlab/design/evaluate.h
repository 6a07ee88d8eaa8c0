// One report for a pattern designer (`patlab evaluate`). For a pattern: its accuracy from the
// geometry (first-order prediction, Cramer-Rao bound, efficiency), the same by Monte-Carlo at one
// patch sigma (the known-correspondence runner), its ID capacity (paper Table II), and how often
// the detector misidentifies it in whole simulated frames (the detect-mode runner).
//
// Each pattern is evaluated alone with two experiments built here, both seeded from
// EvaluateOptions::seed: a pattern's report does not depend on the other patterns evaluated, nor
// on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"
#include "patlab/estimate/bounds.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/runner.h"

namespace patlab::design {

// The ID colour names of generated codebooks, in order (id_colours = N takes the first N).
inline constexpr std::array<const char*, 8> kEvaluateIdColours = {
    "pink", "green", "cyan", "white", "red", "purple", "brown", "grey"};

struct EvaluateOptions {
  double sigma_mm = 1.0;    // part 2: the Monte-Carlo patch sigma (mm)
  int64_t trials = 100000;  // part 2: Monte-Carlo trials
  // Part 3: ID palette sizes, and the symmetry tolerance of parts 3 and 4 (paper section III:
  // 10 mm; the caller checks it, as `patlab ids` does).
  std::vector<int> colour_counts = {2, 3, 4};
  double tolerance_mm = 10.0;
  // Part 4: the patch sigmas (mm) of the misidentification frames, frames per sigma, and the
  // codebook's ID colours (the first N of kEvaluateIdColours). Without id_colours: the codebook
  // <pattern>.codebook.toml next to the pattern file if there is one, else 2 colours.
  std::vector<double> sigmas_mm = {1.0, 2.0, 3.0, 4.0};
  int64_t frames = 1000;
  std::optional<int> id_colours;
  uint64_t seed = 1;
  int threads = 0;  // 0 = all cores; the report does not depend on it
  // Called on the calling thread after part 2's Monte-Carlo point and after each of part 4's
  // sigmas: (units done, 1 + sigmas). Optional; the report does not depend on it.
  std::function<void(int, int)> progress;
};
// Fields named as the flags of `patlab evaluate` ("--sigma"): sigma a patch std > 0 and at most
// 1e6 mm, trials and frames as in experiment files (experiment.h), sigmas a sigma grid, id_colours
// in [1, 8] (the names above), threads >= 0.
std::vector<OptionsProblem> Check(const EvaluateOptions& options);
void Validate(const EvaluateOptions& options);

// Part 1: each estimator's first-order std per mm of patch sigma.
struct GeometryRow {
  estimate::Estimator estimator = estimate::Estimator::kFast;
  estimate::StdPerSigma predicted;
};

// Part 3: the pattern's symmetry and its number of IDs per palette size.
struct IdCapacity {
  detect::Symmetry symmetry;
  std::vector<std::pair<int, uint64_t>> counts;  // (colours, IDs)
};

// Part 4: detect-mode points, one per sigma, with up to 5 robots per team.
struct Misidentification {
  bool run = false;
  std::string skipped_reason;           // when !run
  std::string codebook;                 // "generated" or the codebook file
  std::vector<std::string> id_colours;  // the codebook's colours
  int ids = 0;
  int robots_per_frame = 0;
  sim::DetectRunResult result;
};

struct EvaluationReport {
  EvaluateOptions options;  // as evaluated
  Pattern pattern;
  std::string file;
  estimate::StdPerSigma crlb;         // per mm of patch sigma
  std::vector<GeometryRow> geometry;  // every estimator
  sim::RunResult monte_carlo;         // one point, every estimator
  IdCapacity ids;
  Misidentification misidentification;
};

// Evaluates `pattern` (read from `file`, whose directory may hold its codebook). Validates
// `options` first; throws InputError.
EvaluationReport EvaluatePattern(const Pattern& pattern, const std::string& file,
                                 const EvaluateOptions& options);

// The report as a text table for people (the four parts, numbered), and all reports as one JSON
// object {"tool", "version", "seed", "patterns": [...]}.
std::string EvaluationText(const EvaluationReport& report);
std::string EvaluationJson(const EvaluateOptions& options,
                           const std::vector<EvaluationReport>& reports);

}  // namespace patlab::design

// Experiment files (experiments/*.toml; format documented in README.md, "Experiment files").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/pattern.h"
#include "estimate/estimators.h"
#include "sim/noise.h"

namespace patlab::sim {

struct Experiment {
  std::string name;
  std::string description;
  std::string source_file;                          // the experiment file, for the manifest
  std::vector<Pattern> patterns;                    // in file order
  std::vector<std::string> pattern_files;           // resolved paths, same order
  std::vector<estimate::Estimator> estimators;      // in file order, no duplicates
  std::vector<double> sigmas_mm;                    // the patch sigma grid, >= 0, increasing
  int64_t trials = 100000;                          // per data point, >= 2
  uint64_t seed = 1;                                // experiment seed
  double field_length_mm = 2800.0;                  // random pose x range: +-length/2
  double field_width_mm = 2300.0;                   // random pose y range: +-width/2
  NoiseModel noise;
  estimate::Options ml_options;
};

// Reads an experiment file. Pattern names resolve to <patterns_dir>/<name>.toml, where
// patterns_dir defaults to ../patterns relative to the experiment file (key `patterns_dir`).
Experiment LoadExperimentFile(const std::string& path);

// Command-line overrides, applied after loading and validated like the file.
struct Overrides {
  int64_t trials = 0;        // 0: keep
  bool has_seed = false;
  uint64_t seed = 0;
  std::vector<double> sigmas_mm;  // empty: keep
};
void ApplyOverrides(const Overrides& overrides, Experiment* experiment);

}  // namespace patlab::sim

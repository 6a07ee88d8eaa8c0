// Experiment files (experiments/*.toml; format in docs/file-formats.md): the Monte-Carlo
// experiments of sim/experiment.h, known correspondence or detect mode.
#pragma once

#include <string>

#include "patlab/sim/experiment.h"

namespace patlab::formats {

// Reads an experiment file. Pattern names resolve to <patterns_dir>/<name>.toml, where
// patterns_dir defaults to ../patterns relative to the experiment file (key `patterns_dir`).
// With correspondence = "detect" they name [[pattern]]s of the [detect] settings file instead,
// and trials, estimators, ml and patterns_dir are rejected (the detector settings hold them).
sim::Experiment LoadExperimentFile(const std::string& path);

}  // namespace patlab::formats

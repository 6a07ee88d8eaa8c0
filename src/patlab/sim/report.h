// The simulator's results as text: a tidy CSV (one row per pattern x estimator x sigma) and a
// JSON manifest (inputs, seed, version, timings). Column meanings: docs/file-formats.md.
#pragma once

#include <span>
#include <string>

#include "patlab/sim/detect_runner.h"
#include "patlab/sim/runner.h"

namespace patlab::sim {

// The CSV. Deterministic: the same results give the same bytes.
std::string ResultsCsv(const Experiment& experiment, const RunResult& result);
// Its rows (no header) for points of a run whose noise model NoiseModel::Describe() gives
// `noise`: what `patlab merge` writes for points it finishes from trial-range shards.
std::string ResultsCsvRows(const std::string& noise, std::span<const PointResult> points);

// The manifest. `command_line` and `outputs` are recorded as given.
std::string ManifestJson(const Experiment& experiment, const RunResult& result,
                         const std::string& command_line, const std::vector<std::string>& outputs);

// Detect mode (correspondence = "detect"): one row per pattern x false-blob rate x sigma
// (columns: docs/file-formats.md), and its manifest, with the same common fields.
std::string DetectResultsCsv(const Experiment& experiment, const DetectRunResult& result);
// Its rows (no header), as ResultsCsvRows: what `patlab merge` writes for detect-mode points it
// finishes from trial-range shards.
std::string DetectResultsCsvRows(const std::string& noise,
                                 std::span<const DetectPointResult> points);
std::string DetectManifestJson(const Experiment& experiment, const DetectRunResult& result,
                               const std::string& command_line,
                               const std::vector<std::string>& outputs);

}  // namespace patlab::sim

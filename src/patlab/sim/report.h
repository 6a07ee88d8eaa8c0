// The simulator's results as text: a tidy CSV (one row per pattern x estimator x sigma) and a
// JSON manifest (inputs, seed, version, totals, the files written). Column meanings:
// docs/file-formats.md. Both are the same bytes on every machine, at every thread count and for
// every way of running the sweep (one process or merged shards): how the run went (its command
// line, threads and timings) is printed by the tool, not recorded with the results.
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

// The manifest; `outputs` are recorded by file name (io::OutputNames).
std::string ManifestJson(const Experiment& experiment, const RunResult& result,
                         const std::vector<std::string>& outputs);

// Detect mode (correspondence = "detect"): one row per pattern x false-blob rate x sigma
// (columns: docs/file-formats.md), and its manifest, with the same common fields.
std::string DetectResultsCsv(const Experiment& experiment, const DetectRunResult& result);
// Its rows (no header), as ResultsCsvRows: what `patlab merge` writes for detect-mode points it
// finishes from trial-range shards.
std::string DetectResultsCsvRows(const std::string& noise,
                                 std::span<const DetectPointResult> points);
std::string DetectManifestJson(const Experiment& experiment, const DetectRunResult& result,
                               const std::vector<std::string>& outputs);

}  // namespace patlab::sim

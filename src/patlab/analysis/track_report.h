// What the track experiment reports (track.h gives the whole picture): the paper's Table I, the
// Wilcoxon tests between disc sizes, and the files they are written to.
#pragma once

#include <string>
#include <vector>

#include "patlab/analysis/track_options.h"
#include "patlab/analysis/track_runner.h"
#include "patlab/stats/error_stats.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::analysis {

// Table I rows: per subject, std with 95% CI of the estimated and of the true error, per axis.
struct TableRow {
  std::string subject;
  // Each interval on the effective dof of the autocorrelated errors (error_stats.h); the iid
  // intervals and the effective sizes beside them.
  stats::StdWithCi est_x, est_y, true_x, true_y;
  stats::StdWithCi est_x_iid, est_y_iid, true_x_iid, true_y_iid;
  stats::EffectiveSize est_size_x, est_size_y, true_size_x, true_size_y;
  double true_mean_x_mm = 0.0, true_mean_y_mm = 0.0;  // bias of the measurement
  double est_lag1_x = 0.0, est_lag1_y = 0.0;          // lag-1 autocorrelation (Fig. 6)
  bool has_theta = false;
  stats::StdWithCi est_theta, true_theta;
  int missed_frames = 0;
};
// Throws InputError when a subject was found in fewer than 2 frames.
std::vector<TableRow> MakeTable(const TrackResult& result);

// Wilcoxon signed-rank tests between the disc diameters on paired |error| (same run, same frame),
// per axis (x, y, and the combined |(x, y)|), for the estimated and the true errors
// (error_stats.h, shared with `patlab analyze`).
using SizeTest = stats::PairedTest;
std::vector<SizeTest> MakeSizeTests(const TrackResult& result);

// Output files (CSV text).
std::string TableCsv(const std::vector<TableRow>& rows);
std::string SizeTestsCsv(const std::vector<SizeTest>& tests);
// Per-sample errors of every subject and run: with decimate > 1 only every decimate-th kept
// sample and the sample after it (so that lag-1 pairs, Fig. 6, survive the decimation).
std::string ErrorsCsv(const TrackOptions& options, const TrackResult& result, int decimate);

// The manifest (JSON text): every option, the run setups, Table I and the output files (by
// name). How long the run took is printed by the tool, not recorded with the results.
std::string TrackManifestJson(const TrackOptions& options, const TrackResult& result,
                              const std::vector<TableRow>& table,
                              const std::vector<std::string>& outputs);

}  // namespace patlab::analysis

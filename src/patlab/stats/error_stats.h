// The section-II statistics of a set of per-sample errors (Bruce & Veloso 2003, Table I and the
// Wilcoxon tests), shared by the simulated track experiment (`patlab track`, track_report.h) and
// the analysis of measured tracks (`patlab analyze`, analyze.h): per subject the std with its 95%
// interval on each axis (stats/summary.h), the lag-k autocorrelation (stats/smoothing.h, Fig. 6),
// and Wilcoxon signed-rank tests between subjects on |error| paired by run and frame
// (stats/wilcoxon.h). Where the errors come from (smoothing residuals or sample minus truth) is
// the caller's business.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::stats {

// Errors of one subject over a stretch of consecutive kept samples: one run of the track
// experiment, or one gap-free segment of a measured track. frame increases strictly; theta is
// empty or as long as frame.
struct ErrorSegment {
  int run = 0;  // index of the run, the pairing key with frame
  std::vector<int64_t> frame;
  std::vector<double> x, y, theta;
};

struct ErrorSummary {
  stats::StdWithCi x, y;
  double mean_x = 0.0, mean_y = 0.0;
  // Mean over segments of the lag-k autocorrelation within each segment (segments with fewer
  // than lag + 2 samples left out; 0 when none is left).
  double lag_x = 0.0, lag_y = 0.0;
  bool has_theta = false;
  stats::StdWithCi theta;
};
// The std (95% interval) of x, y and theta pooled over `segments`, their means, and the lag-`lag`
// autocorrelation. Needs at least 2 samples in all (InputError from stats otherwise).
ErrorSummary SummariseErrors(const std::vector<ErrorSegment>& segments, int lag = 1);

// A Wilcoxon signed-rank test between subjects a and b on |error| of the same run and frame.
struct PairedTest {
  std::string error;  // what the errors are: "est" (smoothing residual) or "true"
  std::string axis;   // "x", "y" or "xy" (the length of (x, y))
  std::string a, b;
  double median_abs_a_mm = 0.0, median_abs_b_mm = 0.0;  // upper medians of the paired |error|
  stats::WilcoxonResult result;                         // two-sided, normal approximation
};
// Every pair a < b of `subjects` (names[k] the name of subjects[k], each sorted by run then
// frame), per axis x, y, xy; pairs without common samples are left out.
std::vector<PairedTest> PairedAbsErrorTests(
    const std::string& error, const std::vector<std::string>& names,
    const std::vector<const std::vector<ErrorSegment>*>& subjects);

// The tests as CSV: error,axis,a,b,n,median_abs_a_mm,median_abs_b_mm,r_plus,r_minus,z,p_value,
// smaller (smaller: the subject with the smaller errors by the sign of R+ - R-).
std::string PairedTestsCsv(const std::vector<PairedTest>& tests);

}  // namespace patlab::stats

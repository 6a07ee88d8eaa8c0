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

#include "patlab/stats/effective_n.h"
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

// Consecutive errors of a track are correlated (a pattern moves a fraction of a pixel per frame,
// so its quantisation error repeats), and the chi-square interval of a std on n - 1 degrees of
// freedom is then too narrow by about sqrt(tau). Each std's interval is therefore taken on
// (n - 1) / tau degrees of freedom, tau = 1 + 2 sum_k r_k^2 estimated from the errors themselves
// (stats/effective_n.h: Bartlett's variance inflation, the autocorrelations of each segment
// about its own mean pooled over segments, summed up to the first lag inside the white-noise
// band 2 / sqrt(n)); the iid interval is kept beside it.
inline constexpr const char* kStdIntervalMethod =
    "chi-square on (n - 1) / tau dof, tau = 1 + 2 sum_k r_k^2 (Bartlett), r_k pooled over "
    "segments, summed to the first lag with |r_k| < 2 / sqrt(n)";

struct ErrorSummary {
  stats::StdWithCi x, y;  // the std and its interval on the effective dof (above)
  double mean_x = 0.0, mean_y = 0.0;
  // Mean over segments of the lag-k autocorrelation within each segment (segments with fewer
  // than lag + 2 samples left out; 0 when none is left).
  double lag_x = 0.0, lag_y = 0.0;
  bool has_theta = false;
  stats::StdWithCi theta;
  // The same stds with the iid interval (n - 1 dof), and the effective sizes behind x, y, theta.
  stats::StdWithCi x_iid, y_iid, theta_iid;
  stats::EffectiveSize size_x, size_y, size_theta;
};
// The std (95% interval on the effective dof, and the iid one) of x, y and theta pooled over
// `segments`, their means, and the lag-`lag` autocorrelation. `min_lags`: the lags of the
// autocorrelation that tau sums whatever the white-noise band (stats::VarianceEffectiveSize):
// 2 radius for residuals of a smoothing kernel of that radius, which are correlated over that
// reach and cross zero inside it; 0 for errors against the truth. Needs at least 2 samples in all
// (InputError from stats otherwise).
ErrorSummary SummariseErrors(const std::vector<ErrorSegment>& segments, int lag = 1,
                             int min_lags = 0);

// The iid interval is off when tau >= kIidWarningTau (its width by sqrt(tau) >= 1.1): a line
// naming `what` (e.g. "subject a, est x"), the lag-1 autocorrelation and tau, or "" when not.
inline constexpr double kIidWarningTau = 1.21;
std::string IidIntervalWarning(const std::string& what, const stats::EffectiveSize& size);

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

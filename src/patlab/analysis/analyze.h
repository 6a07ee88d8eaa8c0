// `patlab analyze`: the paper's section-II error analysis (Bruce & Veloso 2003, Table I, the
// Wilcoxon tests, Figs. 2, 3 and 6) on MEASURED tracks -- tracks without ground truth, read from
// CSV files (e.g. written by `patlab detect --track`). Each sample's error is estimated as the
// sample minus the Gaussian-smoothed track (sigma = 10 samples, stats/smoothing.h); the
// statistics of those residuals are error_stats.h's, shared with the simulated experiment
// (`patlab track`). docs/analyze.md has the method, its bias and its limits. Other detrendings
// (AnalyzeOptions::detrend): a straight line or a mean per segment. Each std's 95% interval
// allows for the errors' autocorrelation (error_stats.h, kStdIntervalMethod).
//
// Gaps. A track is split where its frame numbers jump (missed frames); each gap-free segment is
// smoothed alone (never across a gap) and only where the whole kernel lies inside it: the first
// and last `radius` samples of a segment (radius = the kernel's, 40 for sigma = 10) are dropped,
// because the reflecting boundary bends a moving track. A segment shorter than 2 radius + 1
// samples has no such sample and is skipped (counted in the report).
//
// Bias. For white errors of std s the residual has std s sqrt(1 - 2 w0 + sum_k w_k^2) (w the
// kernel; 0.974 s for sigma = 10, stats::ResidualStdFactor); AnalyzeOptions::correct_bias divides
// the estimated stds and their intervals by that factor.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/options.h"
#include "patlab/stats/error_stats.h"
#include "patlab/stats/smoothing.h"

namespace patlab::analysis {

// Column names of a track CSV (header row, then one sample a row; docs/file-formats.md).
struct TrackColumns {
  std::string frame = "frame";      // integer frame number, strictly increasing per subject and run
  std::string subject = "subject";  // optional: absent, the file holds one subject, "track"
  std::string run = "run";          // optional: absent, each file is one run named by its path
  std::string x = "x_mm";
  std::string y = "y_mm";
  std::string theta = "theta_rad";  // optional: absent, no orientation analysis
  // An optional column named explicitly (a CLI flag) must be there.
  bool require_subject = false, require_run = false, require_theta = false;
};
// Every name non-empty, without comma or line break, and no two the same.
std::vector<OptionsProblem> Check(const TrackColumns& columns);
void Validate(const TrackColumns& columns);

// One subject over one run, as read.
struct MeasuredTrack {
  std::string subject, run;
  std::string file;    // where it was read from, for messages
  int first_line = 0;  // its first row
  std::vector<int64_t> frame;
  std::vector<double> x, y, theta;  // theta empty without a theta column
};

// Reads a track CSV: lines split on '\n' (a trailing '\r' dropped), blank lines and lines starting
// with '#' skipped, cells trimmed of blanks and of one pair of double quotes. Tracks in order of
// first appearance. Throws InputError "file:line: what; expected what" for: no header, a missing
// column, a row without a needed cell, a frame that is not an integer, a number that is not finite
// (NaN, inf) or not a number, a frame not after the previous frame of its subject and run, no rows.
std::vector<MeasuredTrack> ReadTrackCsv(const std::string& path, const TrackColumns& columns);
// The same on text; `source_name` stands for the file in messages and is the default run name.
std::vector<MeasuredTrack> ParseTrackCsv(std::string_view text, const std::string& source_name,
                                         const TrackColumns& columns);

// What a sample's error is measured against (the trend of its gap-free segment): the
// Gaussian-smoothed track (the paper's, the default; the segment's first and last kernel radius
// samples dropped), the least-squares straight line through the segment's samples against their
// frame index (a subject moving at constant speed), or the segment's mean (a subject at rest).
enum class Detrend { kSmooth, kLinear, kNone };
inline constexpr EnumNames<Detrend, 3> kDetrendNames{{{
    {Detrend::kSmooth, "smooth"},
    {Detrend::kLinear, "linear"},
    {Detrend::kNone, "none"},
}}};

struct AnalyzeOptions {
  Detrend detrend = Detrend::kSmooth;
  stats::SmoothingOptions smoothing;  // sigma_samples > 0 (the paper's 10), truncate_sigmas
  int lag = 1;                        // lag of the reported autocorrelation, >= 1 (Fig. 6: 1)
  // Divide the estimated stds and their intervals by stats::ResidualStdFactor (white errors;
  // detrend smooth only: a line or a mean costs 2 or 1 of a segment's degrees of freedom, a bias
  // below 0.1% for segments of 1000 samples, and the factor is then 1).
  bool correct_bias = false;
  // Rotate each segment's errors into its direction of travel (x along the line from the first to
  // the last smoothed position of the kept samples, y across it: the paper's convention) instead
  // of the file's axes. Needs detrend smooth or linear (a mean has no direction).
  bool along_travel = false;
  // Called after each subject is analysed (subjects done, subjects in all); empty = no reports.
  std::function<void(int, int)> progress;
};
std::vector<OptionsProblem> Check(const AnalyzeOptions& options);
void Validate(const AnalyzeOptions& options);

struct SubjectAnalysis {
  std::string subject;
  stats::ErrorSummary est;  // smoothing residuals (bias-corrected with correct_bias)
  bool has_truth = false;
  stats::ErrorSummary truth;  // sample - truth over the same samples (with a truth file)
  size_t samples = 0;         // read
  int segments = 0;           // gap-free segments analysed
  int skipped_segments = 0;
  size_t skipped_samples = 0;                                // in the skipped segments
  std::vector<stats::ErrorSegment> est_errors, true_errors;  // sorted by run, then frame
};

struct AnalyzeReport {
  AnalyzeOptions options;
  // One line per std whose iid interval is off (stats::IidIntervalWarning), for stderr.
  std::vector<std::string> warnings;
  std::vector<std::string> runs;  // names; ErrorSegment::run indexes them
  std::vector<SubjectAnalysis> subjects;
  std::vector<stats::PairedTest> tests;  // "est" and, with a truth file, "true"
  int radius = 0;                // kernel radius: samples dropped per segment end (0 unless smooth)
  int min_segment = 0;           // smooth: 2 radius + 1; linear: 3; none: 2
  double residual_factor = 0.0;  // stats::ResidualStdFactor (smooth), 1 otherwise
  double white_noise_lag = 0.0;  // lag-k autocorrelation of the residuals of white noise (smooth)
};

// Analyses `tracks` (several subjects and runs). `truth` (optional, same subjects and runs, every
// analysed frame present) adds the true errors; a track's truth is the truth track of the same
// subject and run, or else the only truth track of its subject. Throws InputError "file:line: ..."
// for a subject without any segment long enough, or a truth row missing.
AnalyzeReport AnalyzeTracks(const std::vector<MeasuredTrack>& tracks, const AnalyzeOptions& options,
                            const std::vector<MeasuredTrack>* truth = nullptr);
// The same, freeing each track's samples as soon as it is analysed (the tracks keep their names;
// their samples are empty afterwards): the errors reuse the samples' memory, which saves a fresh
// page for every 512 samples of a large input.
AnalyzeReport AnalyzeTracks(std::vector<MeasuredTrack>&& tracks, const AnalyzeOptions& options,
                            const std::vector<MeasuredTrack>* truth = nullptr);

// Table I: one row per subject (docs/analyze.md lists the columns).
std::string AnalyzeTableCsv(const AnalyzeReport& report);
// Per-sample errors: subject,run,frame,est_x,est_y,est_theta[,true_x,true_y,true_theta].
std::string AnalyzeErrorsCsv(const AnalyzeReport& report);
// The same text handed to `sink` in pieces of about 256 kB (the CLI streams it into its file:
// no 35 MB string for a million samples). The concatenation of the pieces is AnalyzeErrorsCsv.
void WriteAnalyzeErrorsCsv(const AnalyzeReport& report,
                           const std::function<void(std::string_view)>& sink);
// The manifest (JSON): inputs, options, the table and the output files (by name).
std::string AnalyzeManifestJson(const AnalyzeReport& report, const std::vector<std::string>& inputs,
                                const std::vector<std::string>& outputs);

}  // namespace patlab::analysis

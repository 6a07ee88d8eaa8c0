// The single-patch track experiment of Bruce & Veloso 2003, section II, in simulation: white
// discs (and optionally a whole pattern) carried at constant speed across the view of a camera
// looking straight down, every frame rendered (render.h), segmented by the CMVision pipeline
// (segment.h) and converted to mm (camera.h). The paper had no ground truth and estimated each
// sample's error as the sample minus the Gaussian-smoothed track (sigma = 10 samples); here the
// truth is known, so both that estimate and the true error are reported.
//
// Geometry. World x, y on the floor (mm), z up; the camera is a distortion-free pinhole at
// (0, 0, camera.height_mm) looking straight down, image right = world x, image down = world -y,
// so the patch plane is fronto-parallel and a disc images as a disc of radius
// r_mm * focal_length_px / (height_mm - plane_height_mm). The platform starts near the left edge
// of the view and travels at speed_mm_per_s along heading h (a small angle to the image rows,
// random per run); the subjects ride side by side on it, spaced spacing_mm apart across the
// direction of travel. Errors are reported in the track frame: x along the travel, y across it
// (the paper's convention).
//
// Randomness (docs/architecture.md rule 1): everything is a pure function of (seed, run, frame, pixel):
//   run setup (heading, start)   RandomStream(seed, kRunStream, run)
//   camera jitter of a frame     RandomStream(seed, kJitterStream, run << 32 | frame)
//   intensity noise of a pixel   Philox block (frame, run, kPixelStream, y * width + x)
// so the three diameters of a run see the same frames (paired samples, as on the paper's single
// platform) and results do not depend on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "patlab/core/pattern.h"
#include "patlab/stats/smoothing.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"
#include "patlab/vision/render.h"

namespace patlab::sim {

inline constexpr uint32_t kRunStream = 0x7472756e;     // "trun"
inline constexpr uint32_t kJitterStream = 0x746a6974;  // "tjit"
inline constexpr uint32_t kPixelStream = 0x7470786c;   // "tpxl"

struct TrackCamera {
  double height_mm = 3000.0;  // camera centre above the floor (paper: 3 m). > plane height
  int image_width_px = 640;   // sensor size; the track must stay inside it
  int image_height_px = 480;
  // Focal length in pixels. 686 px at 3 m gives 4.37 mm/px on the floor, the 2.8 m F180 field
  // across 640 px. Larger: finer pixels, smaller view. > 0.
  double focal_length_px = 686.0;
};

struct TrackOptions {
  std::string name = "table1";  // output base name
  std::string description;
  uint64_t seed = 2003;
  int runs = 5;  // independent passes across the view (paper: 5). 1..1000

  // Subjects: one white disc per diameter (paper: 40, 50, 60 mm), each > 0, distinct, and
  // optionally a whole pattern (pattern_file non-empty; its patches all rendered in the patch
  // colour, pose from estimate::Fast with known correspondence) for the paper's Fig. 6 bottom.
  std::vector<double> diameters_mm = {40.0, 50.0, 60.0};
  std::string pattern_file;  // "" = no pattern subject
  Pattern pattern;           // loaded from pattern_file

  // Platform.
  int samples_per_run = 2570;    // frames per run (paper: ~2570). >= 2 * trim_samples + 3
  double rate_hz = 30.0;         // frames per second (paper: 30). > 0
  double speed_mm_per_s = 23.0;  // platform speed (paper: ~23 mm/s). >= 0; 0 = static subjects
  // Heading of the travel relative to the image rows, uniform in [-max, max] per run. 0 keeps the
  // across-track sub-pixel phase fixed for a whole run, so its quantisation error is a constant
  // bias. In [0, 45].
  double heading_max_deg = 2.0;
  // Start of the platform centre: x = -(travel length) / 2 + U(-start_jitter, start_jitter),
  // y = U(-lateral_range / 2, lateral_range / 2). >= 0 each.
  double lateral_range_mm = 200.0;
  double start_jitter_mm = 20.0;
  double spacing_mm = 150.0;     // distance between neighbouring subjects across the track. > 0
  double plane_height_mm = 0.0;  // height of the patch tops; < camera height

  TrackCamera camera;

  // Rendering and segmentation: grey levels (the same on R, G, B); a pixel is classed as patch
  // when its level >= threshold (CMVision box r, g, b in [threshold, 255]).
  int background_level = 40;  // 0..255
  int patch_level = 230;      // 0..255, != background
  int threshold_level = 135;  // strictly between background and patch levels
  int supersampling = 8;      // render.h sub-samples per pixel side, 1..32

  // Noise. pixel_sigma: std of Gaussian intensity noise (grey levels) added to every pixel
  // of every frame (same on R, G, B), independent between pixels and frames; it makes boundary
  // pixels flicker. jitter_sigma_px: std of a per-frame shift of the whole image (both axes, px),
  // common to every subject of a frame. >= 0 each.
  double pixel_sigma = 0.0;
  double jitter_sigma_px = 0.0;

  // Analysis (paper section II): residuals from a Gaussian smoothing of each run's track, sigma
  // in samples; the first and last trim_samples of every run are dropped from all statistics
  // (the reflected boundary of the smoothing bends a moving track there: at 23 mm/s and sigma
  // 10 the end samples would be off by ~6 mm). trim_samples >= 0.
  double smoothing_sigma_samples = 10.0;  // > 0
  int trim_samples = 40;

  std::string source_file;  // for messages and the manifest
};

// One problem with the options: the TOML table ("" = top level) and key it comes from, and the
// complete message, e.g. "pixel_sigma in [noise] is -1; expected a number >= 0".
struct TrackProblem {
  std::string table;
  std::string key;
  std::string message;
};
// Every constraint on TrackOptions, checked in one place (docs/architecture.md rule 4); empty when valid.
// Geometry is checked too: every subject must stay inside the image for the whole run.
std::vector<TrackProblem> CheckTrackOptions(const TrackOptions& options);
// Throws InputError with the first problem's message.
void Validate(const TrackOptions& options);

// Reads an experiment file (format: experiments/table1.toml, documented there). Problems are
// InputErrors "file:line: message" pointing at the offending key.
TrackOptions LoadTrackExperiment(const std::string& path);
TrackOptions ParseTrackExperiment(std::string_view text, const std::string& source_name);

// Camera mm per pixel on the patch plane.
double MmPerPixel(const TrackOptions& options);

// One subject over one run: per kept sample (after trimming), errors in the track frame (mm;
// theta in rad, patterns only). est_* = sample - Gaussian-smoothed track (the paper's estimate);
// true_* = sample - truth. Missing samples (no region found) are interpolated for the smoothing
// and left out here; missed_frames counts them.
struct SubjectRun {
  std::vector<int> sample;  // frame index of each kept sample
  std::vector<double> est_x_mm, est_y_mm, true_x_mm, true_y_mm;
  std::vector<double> est_theta_rad, true_theta_rad;  // patterns only
  int missed_frames = 0;
};

struct RunSetup {
  double heading_rad = 0.0;
  Vec2 start_mm = Vec2::Zero();  // platform centre at frame 0
};
RunSetup MakeRunSetup(const TrackOptions& options, int run);

// Subjects: the discs in diameters_mm order, then the pattern (if any).
int NumSubjects(const TrackOptions& options);
// True pose of subject `subject` in frame `frame` of a run (theta = the run's heading).
Pose2 TruthPose(const TrackOptions& options, const RunSetup& setup, int frame, int subject);
// Re-measures one subject in one frame exactly as RunTrack does (docs/architecture.md rule 3: any sample
// can be replayed alone): a disc's centroid (theta 0), or the pattern's fast-estimator pose.
// False when a region was not found.
bool MeasureSubject(const TrackOptions& options, int run, int frame, int subject, Pose2* measured);

struct TrackResult {
  std::vector<std::string> subjects;          // "40mm", "50mm", "60mm", then the pattern name
  std::vector<std::vector<SubjectRun>> data;  // [subject][run]
  std::vector<RunSetup> setups;               // per run
  double wall_seconds = 0.0;
  double measure_seconds = 0.0;   // stage 1: render, segment, camera (and fast estimator)
  double analysis_seconds = 0.0;  // stage 2: smoothing residuals, track-frame errors
  int threads = 0;
};

struct TrackRunOptions {
  int threads = 0;  // 0 = all cores; results do not depend on it
};

// Runs the whole experiment (TBB over blocks of frames, results in fixed slots). Validates first.
TrackResult RunTrack(const TrackOptions& options, const TrackRunOptions& run_options = {});

// The measured world position (mm) of a single disc of diameter_mm at truth position world_mm in
// frame `frame` of run `run` (jitter and noise included), or false when no region was found.
// Exposed for tests and replays.
bool MeasureDisc(const TrackOptions& options, int run, int frame, const Vec2& world_mm,
                 double diameter_mm, Vec2* measured_mm);

// Table I rows: per subject, std with 95% CI of the estimated and of the true error, per axis.
struct TableRow {
  std::string subject;
  stats::StdWithCi est_x, est_y, true_x, true_y;
  double true_mean_x_mm = 0.0, true_mean_y_mm = 0.0;  // bias of the measurement
  double est_lag1_x = 0.0, est_lag1_y = 0.0;          // lag-1 autocorrelation (Fig. 6)
  bool has_theta = false;
  stats::StdWithCi est_theta, true_theta;
  int missed_frames = 0;
};
std::vector<TableRow> MakeTable(const TrackResult& result);

// Wilcoxon signed-rank tests between the disc diameters on paired |error| (same run, same frame),
// per axis (x, y, and the combined |(x, y)|), for the estimated and the true errors.
struct SizeTest {
  std::string error;  // "est" or "true"
  std::string axis;   // "x", "y", "xy"
  std::string a, b;   // subjects
  double median_abs_a_mm = 0.0, median_abs_b_mm = 0.0;
  stats::WilcoxonResult result;
};
std::vector<SizeTest> MakeSizeTests(const TrackResult& result);

// White-noise factor of the paper's estimator: for iid errors of std s, the smoothing residual
// has std s * sqrt(1 - 2 w_0 + sum_k w_k^2), w the normalised kernel (0.974 for sigma = 10).
double ResidualStdFactor(const stats::SmoothingOptions& options);

// Output files (CSV text).
std::string TableCsv(const std::vector<TableRow>& rows);
std::string SizeTestsCsv(const std::vector<SizeTest>& tests);
// Per-sample errors of every subject and run: with decimate > 1 only every decimate-th kept
// sample and the sample after it (so that lag-1 pairs, Fig. 6, survive the decimation).
std::string ErrorsCsv(const TrackOptions& options, const TrackResult& result, int decimate);

}  // namespace patlab::sim

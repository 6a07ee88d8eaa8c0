// Options of the single-patch track experiment of Bruce & Veloso 2003, section II (track.h gives
// the whole picture): the camera, the platform and its subjects, rendering, noise and analysis,
// with every constraint checked in one place (docs/architecture.md rule 4).
#pragma once

#include <string>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/core/pattern.h"

namespace patlab::analysis {

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
  int patch_level = 230;      // 0..255, above background
  int threshold_level = 135;  // above background, at most the patch level
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
  double smoothing_sigma_samples = 10.0;  // in (0, 10000]
  int trim_samples = 40;

  std::string source_file;  // for messages and the manifest
};

// Every constraint on TrackOptions (core/options.h). Fields are named as the experiment file
// spells them: "runs", "platform.spacing_mm", "noise.pixel_sigma". When every field is in range,
// the geometry is checked too: neighbouring subjects must not touch and every subject must stay
// inside the image for the whole run.
std::vector<OptionsProblem> Check(const TrackOptions& options);
// Throws InputError with the first problem's message.
void Validate(const TrackOptions& options);

// Background pixels around a disc in its render window (track_runner.cpp); the geometry check
// keeps them inside the image too.
inline constexpr int kWindowMarginPx = 3;

// Camera mm per pixel on the patch plane.
double MmPerPixel(const TrackOptions& options);
// Whether a pattern rides on the platform after the discs.
bool HasPattern(const TrackOptions& options);
// Subjects: the discs in diameters_mm order, then the pattern (if any).
int NumSubjects(const TrackOptions& options);
// "40mm", "50mm", "60mm", then the pattern's name: how results name the subjects.
std::vector<std::string> SubjectNames(const TrackOptions& options);
// Distance the platform travels in one run (mm).
double TravelMm(const TrackOptions& options);
// Across-track offset of subject k on the platform (mm): centred, spacing_mm apart.
double SubjectOffsetMm(const TrackOptions& options, int subject);

}  // namespace patlab::analysis

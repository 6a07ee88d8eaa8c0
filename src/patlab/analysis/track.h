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
// The experiment, split by concept:
//   track_options.h  TrackOptions and their Check/Validate, the platform geometry
//   track_runner.h   rendering, measuring, the run (RunTrack) and single-frame replay
//   track_report.h   Table I, the size tests, the CSV files and the manifest
// This header includes all three, for callers that want the whole experiment; its experiment
// files (experiments/table1.toml) are read by formats/track_file.h.
#pragma once

#include "patlab/analysis/track_options.h"
#include "patlab/analysis/track_report.h"
#include "patlab/analysis/track_runner.h"

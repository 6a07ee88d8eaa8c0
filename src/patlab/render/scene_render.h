// Synthetic camera frames of a robot-soccer field: robots wearing a colour-patch pattern (e.g.
// the SSL standard pattern) and a ball at known poses, seen through the same camera model the
// vision pipeline inverts (camera.h), with optics blur and per-pixel colour noise. What it is
// for: a frame whose true poses are known exactly, so the real-frame path (image -> CMVision
// regions -> blobs -> detector) can be tested end to end on any clone of the repository
// (tests/data/golden, docs/render.md), and the detector's accuracy on pixels measured against
// ground truth.
//
// How a frame is made, in order:
//  1. geometry: every robot is a top cover (colour "body", robot_radius_mm) with the pattern's
//     patches on it, at robot_height_mm; the ball is a disc of ball_radius_mm at its centre
//     height (its silhouette seen from above). Each pixel is mapped to the world plane through
//     the camera (pinhole, k1, k2, pose) on an n x n grid of sub-samples and the discs are
//     tested there (render.h RenderWorldDiscs): anti-aliased edges, exact perspective and lens
//     distortion;
//  2. optics: a separable Gaussian blur of blur_sigma_px;
//  3. sensor: independent Gaussian noise of noise_sigma_levels on every channel of every pixel,
//     drawn from core/rng.h keyed by (seed, pixel index), then rounded and clamped to 0..255.
// The same scene and seed give the same image, bit for bit on one machine (up to a level on
// another CPU, from floating-point rounding).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/calib/field.h"
#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"
#include "patlab/render/render.h"

namespace patlab::render {

// How a scene is turned into pixels. Defaults: an SSL-like camera frame.
struct RenderOptions {
  // Image size (px), each in [1, 8192]. Scene files take it from the calibration's image_size_px.
  int width_px = 640;
  int height_px = 480;
  // Sub-samples per pixel side, in [1, 16]: a boundary pixel's coverage is estimated to 1/n
  // (render.h). More costs n^2 per boundary pixel; 4 keeps the error below the noise.
  int supersampling = 4;
  // Height of the plane of the pattern tops (mm), in [0, 1000]. SSL robots are at most 150 mm
  // tall. Must agree with the calibration's height of the key and ID colours used to detect.
  double robot_height_mm = 140.0;
  // Radius of a robot's top cover in colour "body" under its pattern (mm), in [0, 500]; 0 draws
  // the patches on the field directly. SSL robots fit in a 180 mm circle.
  double robot_radius_mm = 90.0;
  // Radius of the ball (mm), in (0, 500]; it is drawn at height ball_radius_mm (its centre). An
  // SSL golf ball is 43 mm across.
  double ball_radius_mm = 21.5;
  // Standard deviation of the optics' Gaussian point spread (px), in [0, 10]; 0 = no blur.
  // Softens edges as a real lens does; larger values shrink small patches' thresholded area.
  double blur_sigma_px = 0.7;
  // Standard deviation of the sensor noise added to each channel of each pixel (8-bit levels),
  // in [0, 64]; 0 = none. Thresholds need a margin of several sigma around each colour.
  double noise_sigma_levels = 3.0;
  // Seed of the noise: pixel (x, y) draws from RandomStream(seed, 0, y * width_px + x).
  uint64_t seed = 1;
};
// Every broken constraint of `options`, one per field (core/options.h), e.g.
// "blur_sigma_px is -1; expected a number in [0, 10] (px)".
std::vector<OptionsProblem> Check(const RenderOptions& options);
// Throws InputError with the first problem of Check.
void Validate(const RenderOptions& options);

// One robot: the team (key) colour name, its codebook ID and the pose of the pattern's origin.
struct RobotPlacement {
  std::string team;
  int id = 0;
  Pose2 pose;
};

// What a frame shows.
struct FieldScene {
  Pattern pattern;            // what every robot wears
  detect::Codebook codebook;  // its IDs: the colour of each ID slot per ID
  // RGB of every colour name drawn: "field" (the background), "body" (robot top covers, when
  // robot_radius_mm > 0), the robots' team colours, the codebook's ID colours, the pattern's
  // fixed colours and ball_colour.
  std::map<std::string, Rgb> colours;
  std::vector<RobotPlacement> robots;
  std::optional<Vec2> ball_mm;  // the ball's position on the floor, if any
  std::string ball_colour = "orange";
  RenderOptions options;
  // When set, the field's painted lines (white, 10 mm wide, render/field_render.h) are drawn on
  // the carpet under the robots, for frames a calibration from the lines can start from.
  std::optional<calib::Field> field;
};

// The colour name of each patch of `pattern` (patch order) on a robot of team colour `team`
// wearing ID `id`: the key is the team colour, an ID slot its codebook colour, a fixed patch its
// own colour. Throws InputError when `id` is not in the codebook.
std::vector<std::string> PatchColours(const Pattern& pattern, const detect::Codebook& codebook,
                                      const std::string& team, int id);

// Renders `scene` as an RGB frame through `camera`, which must be a pinhole camera above the
// robots and the ball. Throws InputError for invalid options, a colour without RGB, an ID not in
// the codebook, or a homography camera (its centre, needed to place the ball, is unknown).
camera::Image RenderScene(const FieldScene& scene, const camera::CameraModel& camera);

// The true poses as CSV: header "team,id,x_mm,y_mm,theta_rad", one row per robot in scene
// order, numbers as they read back exactly (FormatRoundTrip).
std::string TruthCsv(const FieldScene& scene);

}  // namespace patlab::render

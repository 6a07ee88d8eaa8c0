// Whole frames for the simulator: k robots wearing one pattern (distinct IDs per team) and a
// ball at random non-overlapping poses, turned into the blobs a camera would report, with patch
// noise, missing patches, false blobs and colour-label errors; and the score of the detector on
// such frames (detection rate, wrong IDs, false positives, pose errors).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/rng.h"
#include "patlab/detect/blob.h"
#include "patlab/detect/detector.h"

namespace patlab::sim {

// How a patch centre is measured. The default is iid isotropic Gaussian noise of sigma_mm per
// axis; `perturb`, when set, replaces it (the simulator's noise models adapt through it).
struct PatchNoise {
  double sigma_mm = 0.0;
  // Returns the measured centre of a patch whose true centre is `true_mm`, radius `radius_mm`.
  std::function<Vec2(const Vec2& true_mm, double radius_mm, RandomStream& rng)> perturb;
};

struct SceneOptions {
  int pattern = 0;  // index into detect::DetectorConfig::patterns: the pattern every robot wears
  int robots_per_team = 5;  // robots per key (team) colour of that pattern, distinct IDs per team
  // The field robots stand on, centred on the origin (default: SSL division B field, mm).
  double field_length_mm = 6050.0;
  double field_width_mm = 4050.0;
  double robot_radius_mm = 90.0;     // robots stay inside the field
  double min_separation_mm = 180.0;  // between robot centres; 2 * robot_radius_mm = touching
  bool ball = true;                  // a ball blob at a random free spot
  std::string ball_colour = "orange";
  double ball_radius_mm = 21.5;
  double missing_patch_probability = 0.0;  // each patch (key too) independently not seen
  double false_blob_rate_per_m2 = 0.0;     // Poisson rate of false blobs over the field
  double false_blob_radius_min_mm = 10.0;  // false blobs: uniform radius, uniform palette colour
  double false_blob_radius_max_mm = 30.0;
  double colour_error_probability = 0.0;  // each patch independently gets a wrong colour label
};
// The one place scene options are checked (core/options.h), fields named as the keys of an
// experiment's [detect] table (the field dimensions as field_length_mm, field_width_mm):
// robots_per_team an integer in [1, 1000], the field and radii finite and > 0 (a robot must fit
// the field), min_separation_mm >= 0, the probabilities in [0, 1], false_blob_rate_per_m2 in
// [0, 1000] (more is no longer a frame but noise), the false-blob radius range ordered.
std::vector<OptionsProblem> Check(const SceneOptions& options);
void Validate(const SceneOptions& options);

struct SceneRobot {
  int pattern = 0;
  int team_colour = -1;  // palette label of its key patch
  int id = 0;            // codebook ID
  Pose2 pose;
};

struct Scene {
  std::vector<detect::Blob> blobs;  // shuffled: the detector must not depend on their order
  std::vector<SceneRobot> robots;
  Vec2 ball_mm = Vec2::Zero();
  int num_false_blobs = 0;
  int num_missing_patches = 0;
  int num_colour_errors = 0;
};

// Draws one scene for `detector`'s configuration. All randomness comes from `rng` (e.g.
// RandomStream(seed, stream, frame)), so a frame is replayable alone. Throws InputError for
// invalid options, a pattern with too few IDs for robots_per_team, a ball colour not in the
// palette, or a field too small to place the robots.
Scene GenerateScene(const detect::Detector& detector, const SceneOptions& options,
                    const PatchNoise& noise, RandomStream& rng);

// The error of one correct detection: detected minus true pose.
struct PoseError {
  double dx_mm = 0.0;
  double dy_mm = 0.0;
  double dtheta_rad = 0.0;  // wrapped to (-pi, pi]
};

// How one frame's detections compare with the scene. A detection matches a robot of the same
// pattern and team colour whose true position is within match_radius_mm (nearest first, each
// robot at most once).
struct FrameScore {
  int robots = 0;
  int correct = 0;                     // matched, ID right (status ok or missing_patch)
  int wrong_id = 0;                    // matched, a different ID
  int unknown_id = 0;                  // matched, status missing_patch with id -1
  int ambiguous = 0;                   // matched, status ambiguous
  int missed = 0;                      // robots without a matching detection
  int false_positives = 0;             // detections matching no robot
  std::vector<PoseError> pose_errors;  // of the correct detections, in robot order
};
FrameScore ScoreFrame(const Scene& scene, std::span<const detect::Detection> detections,
                      double match_radius_mm = 45.0);

}  // namespace patlab::sim

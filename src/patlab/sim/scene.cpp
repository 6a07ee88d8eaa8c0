#include "patlab/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/portable_math.h"

namespace patlab::sim {

std::vector<OptionsProblem> Check(const SceneOptions& o) {
  const auto probability = [](double p) { return p >= 0.0 && p <= 1.0; };
  const double fits = 0.5 * std::min(o.field_length_mm, o.field_width_mm);
  OptionsChecker check;
  check.IntegerInRange("robots_per_team", o.robots_per_team, 1, 1000)
      .Positive("field_length_mm", o.field_length_mm, "mm")
      .Positive("field_width_mm", o.field_width_mm, "mm")
      .Require("robot_radius_mm", o.robot_radius_mm,
               o.robot_radius_mm > 0.0 && o.robot_radius_mm <= fits,
               "a number > 0 that fits the field")
      .NonNegative("min_separation_mm", o.min_separation_mm, "mm")
      .Positive("ball_radius_mm", o.ball_radius_mm, "mm")
      .Require("missing_patch_probability", o.missing_patch_probability,
               probability(o.missing_patch_probability), "a probability in [0, 1]")
      .InRange("false_blob_rate_per_m2", o.false_blob_rate_per_m2, 0.0, 1000.0)
      .Positive("false_blob_radius_min_mm", o.false_blob_radius_min_mm, "mm")
      .Require("false_blob_radius_max_mm", o.false_blob_radius_max_mm,
               o.false_blob_radius_max_mm >= o.false_blob_radius_min_mm &&
                   std::isfinite(o.false_blob_radius_max_mm),
               "a finite number >= false_blob_radius_min_mm")
      .Require("colour_error_probability", o.colour_error_probability,
               probability(o.colour_error_probability), "a probability in [0, 1]");
  return check.Take();
}

void Validate(const SceneOptions& options) { ThrowFirstProblem(Check(options)); }

namespace {

// Poisson(lambda) as the number of unit-rate exponential gaps that fit in lambda (exact;
// O(lambda)).
int Poisson(double lambda, RandomStream& rng) {
  int count = 0;
  double t = -pmath::Log(rng.Uniform());
  while (t < lambda) {
    ++count;
    t -= pmath::Log(rng.Uniform());
  }
  return count;
}

// Draws a centre at least `clearance_mm` from every centre in `taken`, `margin_mm` inside the
// field (rejection sampling; a field too crowded for 10000 attempts is bad input).
Vec2 PlaceFree(const SceneOptions& o, double margin_mm, double clearance_mm,
               const std::vector<Vec2>& taken, RandomStream& rng) {
  const double half_l = 0.5 * o.field_length_mm, half_w = 0.5 * o.field_width_mm;
  for (int attempt = 0; attempt < 10000; ++attempt) {
    const Vec2 p(rng.Uniform(-half_l + margin_mm, half_l - margin_mm),
                 rng.Uniform(-half_w + margin_mm, half_w - margin_mm));
    bool free = true;
    for (const Vec2& t : taken) free = free && (p - t).norm() >= clearance_mm;
    if (free) return p;
  }
  throw InputError("scene: cannot place " + std::to_string(taken.size() + 1) + " objects " +
                   FormatNumber(clearance_mm) +
                   " mm apart; expected a larger field or fewer robots");
}

// What the robots of one scene share: the pattern, its ID slots and the palette label of each
// codebook colour.
struct RobotKit {
  const detect::DetectorPattern* dp = nullptr;
  std::vector<int> slots;           // detect::IdSlots(pattern)
  std::vector<int> codebook_label;  // per codebook colour
  int num_labels = 0;               // palette size
};

RobotKit MakeRobotKit(const detect::Detector& detector, const SceneOptions& o) {
  const detect::DetectorConfig& config = detector.config();
  if (o.pattern < 0 || o.pattern >= static_cast<int>(config.patterns.size())) {
    throw InputError("scene: pattern is " + std::to_string(o.pattern) +
                     "; expected an index in [0, " + std::to_string(config.patterns.size()) + ")");
  }
  RobotKit kit;
  kit.dp = &config.patterns[o.pattern];
  const int num_ids = static_cast<int>(kit.dp->codebook.entries.size());
  if (o.robots_per_team > num_ids) {
    throw InputError("scene: robots_per_team is " + std::to_string(o.robots_per_team) +
                     "; expected at most " + std::to_string(num_ids) + " (the IDs of " +
                     kit.dp->pattern.name + ")");
  }
  for (const std::string& c : kit.dp->codebook.colours) {
    kit.codebook_label.push_back(detector.ColourLabel(c));
  }
  kit.slots = detect::IdSlots(kit.dp->pattern);
  kit.num_labels = static_cast<int>(config.palette.size());
  return kit;
}

// The palette label patch `i` of a robot with codebook entry `entry` shows.
int PatchLabel(const detect::Detector& detector, const RobotKit& kit, int i,
               const detect::CodebookEntry& entry, int team_label) {
  const Patch& patch = kit.dp->pattern.patches[i];
  if (patch.role == PatchRole::kKey) return team_label;
  if (patch.role == PatchRole::kFixed) return detector.ColourLabel(patch.colour);
  const int slot =
      static_cast<int>(std::find(kit.slots.begin(), kit.slots.end(), i) - kit.slots.begin());
  return kit.codebook_label[entry.colour[slot]];
}

Vec2 MeasurePatch(const PatchNoise& noise, const Vec2& truth, double radius_mm, RandomStream& rng) {
  if (noise.perturb) return noise.perturb(truth, radius_mm, rng);
  Vec2 measured = truth;
  if (noise.sigma_mm > 0.0) {
    const double nx = rng.Normal(), ny = rng.Normal();
    measured += noise.sigma_mm * Vec2(nx, ny);
  }
  return measured;
}

// The robot's patches as blobs: measured, then maybe missing, maybe mislabelled.
void AddRobotBlobs(const detect::Detector& detector, const RobotKit& kit, const SceneOptions& o,
                   const PatchNoise& noise, const SceneRobot& robot,
                   const detect::CodebookEntry& entry, RandomStream& rng, Scene* scene) {
  const Pattern& pattern = kit.dp->pattern;
  for (int i = 0; i < pattern.size(); ++i) {
    const Patch& patch = pattern.patches[i];
    int label = PatchLabel(detector, kit, i, entry, robot.team_colour);
    const Vec2 measured =
        MeasurePatch(noise, robot.pose.Apply(patch.position_mm), patch.radius_mm, rng);
    // Fixed order of draws per patch, whether or not the event happens (replayable).
    const bool missing = rng.Uniform() < o.missing_patch_probability;
    const bool wrong_colour = rng.Uniform() < o.colour_error_probability;
    const int other = static_cast<int>(rng.Below(std::max(1, kit.num_labels - 1)));
    if (missing) {
      ++scene->num_missing_patches;
      continue;
    }
    if (wrong_colour && kit.num_labels > 1) {
      label = other >= label ? other + 1 : other;
      ++scene->num_colour_errors;
    }
    scene->blobs.push_back({measured, label, patch.Area()});
  }
}

// Robots: per team, distinct IDs (partial Fisher-Yates over the codebook). Returns the centres.
std::vector<Vec2> AddRobots(const detect::Detector& detector, const RobotKit& kit,
                            const SceneOptions& o, const PatchNoise& noise, RandomStream& rng,
                            Scene* scene) {
  const detect::DetectorPattern& dp = *kit.dp;
  const int num_ids = static_cast<int>(dp.codebook.entries.size());
  std::vector<Vec2> centres;
  std::vector<int> ids(num_ids);
  for (const std::string& team : dp.key_colours) {
    const int team_label = detector.ColourLabel(team);
    for (int i = 0; i < num_ids; ++i) ids[i] = i;
    for (int r = 0; r < o.robots_per_team; ++r) {
      const int pick = r + static_cast<int>(rng.Below(num_ids - r));
      std::swap(ids[r], ids[pick]);
      SceneRobot robot;
      robot.pattern = o.pattern;
      robot.team_colour = team_label;
      robot.id = dp.codebook.entries[ids[r]].id;
      const Vec2 c = PlaceFree(o, o.robot_radius_mm, o.min_separation_mm, centres, rng);
      centres.push_back(c);
      robot.pose = Pose2{c.x(), c.y(), WrapAngle(rng.Uniform(-std::numbers::pi, std::numbers::pi))};
      scene->robots.push_back(robot);
      AddRobotBlobs(detector, kit, o, noise, robot, dp.codebook.entries[ids[r]], rng, scene);
    }
  }
  return centres;
}

// False blobs: Poisson over the field, uniform position, radius and colour.
void AddFalseBlobs(const SceneOptions& o, int num_labels, RandomStream& rng, Scene* scene) {
  const double half_l = 0.5 * o.field_length_mm, half_w = 0.5 * o.field_width_mm;
  const double area_m2 = o.field_length_mm * o.field_width_mm * 1e-6;
  scene->num_false_blobs = Poisson(o.false_blob_rate_per_m2 * area_m2, rng);
  for (int i = 0; i < scene->num_false_blobs; ++i) {
    const Vec2 p(rng.Uniform(-half_l, half_l), rng.Uniform(-half_w, half_w));
    const double radius = rng.Uniform(o.false_blob_radius_min_mm, o.false_blob_radius_max_mm);
    const int label = static_cast<int>(rng.Below(num_labels));
    scene->blobs.push_back({p, label, std::numbers::pi * radius * radius});
  }
}

}  // namespace

Scene GenerateScene(const detect::Detector& detector, const SceneOptions& o,
                    const PatchNoise& noise, RandomStream& rng) {
  if (const auto problems = Check(o); !problems.empty()) {
    throw InputError("scene: " + problems.front().message);
  }
  const RobotKit kit = MakeRobotKit(detector, o);
  Scene scene;
  const std::vector<Vec2> centres = AddRobots(detector, kit, o, noise, rng, &scene);
  if (o.ball) {
    const int ball_label = detector.ColourLabel(o.ball_colour);
    if (ball_label < 0) {
      throw InputError("scene: ball_colour \"" + o.ball_colour + "\" is not in the palette");
    }
    scene.ball_mm =
        PlaceFree(o, o.ball_radius_mm, o.robot_radius_mm + o.ball_radius_mm, centres, rng);
    scene.blobs.push_back(
        {scene.ball_mm, ball_label, std::numbers::pi * o.ball_radius_mm * o.ball_radius_mm});
  }
  AddFalseBlobs(o, kit.num_labels, rng, &scene);
  // Shuffle (Fisher-Yates).
  for (int i = static_cast<int>(scene.blobs.size()) - 1; i > 0; --i) {
    std::swap(scene.blobs[i], scene.blobs[rng.Below(i + 1)]);
  }
  return scene;
}

FrameScore ScoreFrame(const Scene& scene, std::span<const detect::Detection> detections,
                      double match_radius_mm) {
  FrameScore score;
  const int nr = static_cast<int>(scene.robots.size());
  const int nd = static_cast<int>(detections.size());
  score.robots = nr;
  // Candidate (distance, robot, detection) pairs; nearest first, each side used once.
  struct Pair {
    double d;
    int robot, detection;
  };
  std::vector<Pair> pairs;
  for (int r = 0; r < nr; ++r) {
    const SceneRobot& robot = scene.robots[r];
    for (int d = 0; d < nd; ++d) {
      const detect::Detection& det = detections[d];
      if (det.pattern != robot.pattern || det.team_colour != robot.team_colour) continue;
      const double dist =
          std::hypot(det.pose.x_mm - robot.pose.x_mm, det.pose.y_mm - robot.pose.y_mm);
      if (dist <= match_radius_mm) pairs.push_back({dist, r, d});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return std::tie(a.d, a.robot, a.detection) < std::tie(b.d, b.robot, b.detection);
  });
  std::vector<int> match_of_robot(nr, -1);
  std::vector<char> detection_used(nd, 0);
  for (const Pair& p : pairs) {
    if (match_of_robot[p.robot] >= 0 || detection_used[p.detection]) continue;
    match_of_robot[p.robot] = p.detection;
    detection_used[p.detection] = 1;
  }
  for (int r = 0; r < nr; ++r) {
    const int d = match_of_robot[r];
    if (d < 0) {
      ++score.missed;
      continue;
    }
    const detect::Detection& det = detections[d];
    const SceneRobot& robot = scene.robots[r];
    if (det.status == detect::DetectionStatus::kAmbiguous) {
      ++score.ambiguous;
    } else if (det.id < 0) {
      ++score.unknown_id;
    } else if (det.id != robot.id) {
      ++score.wrong_id;
    } else {
      ++score.correct;
      score.pose_errors.push_back({det.pose.x_mm - robot.pose.x_mm, det.pose.y_mm - robot.pose.y_mm,
                                   WrapAngle(det.pose.theta_rad - robot.pose.theta_rad)});
    }
  }
  for (int d = 0; d < nd; ++d) score.false_positives += detection_used[d] ? 0 : 1;
  return score;
}

}  // namespace patlab::sim

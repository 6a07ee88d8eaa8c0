#include "patlab/detect/detector.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "../expect_error.h"
#include "patlab/core/error.h"
#include "patlab/formats/codebook_file.h"
#include "patlab/formats/detector_settings.h"
#include "test_util.h"

namespace patlab::detect {
namespace {

using namespace testing;  // NOLINT: test helpers

// The exact SSL codebook of frames/README.md (order FL, FR, BL, BR; P = 0, G = 1).
Codebook SslCodebook() {
  const Pattern ssl = LoadPattern("ssl-standard");
  return formats::LoadCodebookFile(
      std::string(PATLAB_SOURCE_DIR) + "/patterns/ssl-standard.codebook.toml", ssl,
      FindSymmetry(ssl, 10.0));
}

DetectorPattern SslDetectorPattern() {
  DetectorPattern dp;
  dp.pattern = LoadPattern("ssl-standard");
  dp.codebook = SslCodebook();
  dp.key_colours = {"blue", "yellow"};
  return dp;
}

void ExpectPose(const Pose2& got, const Pose2& want, double tol_mm, double tol_rad) {
  EXPECT_NEAR(got.x_mm, want.x_mm, tol_mm);
  EXPECT_NEAR(got.y_mm, want.y_mm, tol_mm);
  EXPECT_NEAR(WrapAngle(got.theta_rad - want.theta_rad), 0.0, tol_rad);
}

struct Case {
  const char* pattern;
  std::vector<std::string> id_colours;  // empty: the SSL codebook file
  size_t expected_ids;                  // hand computed (Table II rule)
};

TEST(Detector, EveryPatternAndIdFromExactBlobsAtRandomPoses) {
  const std::vector<Case> cases = {{"simple", {"pink", "green"}, 2},
                                   {"linear", {"pink", "green", "cyan"}, 3},
                                   {"triangle", {"pink", "green", "cyan"}, 8},
                                   {"butterfly", {"pink", "green"}, 16},
                                   {"ssl-standard", {}, 16}};
  for (const Case& c : cases) {
    DetectorPattern dp = c.id_colours.empty()
                             ? SslDetectorPattern()
                             : MakeDetectorPattern(LoadPattern(c.pattern), c.id_colours);
    ASSERT_EQ(dp.codebook.entries.size(), c.expected_ids) << c.pattern;
    Detector detector(MakeConfig({dp}));
    const Pattern& pattern = dp.pattern;
    std::set<int> ids_seen;
    std::vector<Detection> detections;
    RandomStream rng(7, 1, 0);
    for (size_t e = 0; e < dp.codebook.entries.size(); ++e) {
      for (int trial = 0; trial < 20; ++trial) {
        const Pose2 pose = RandomPose(rng);
        const int team = trial % 2 == 0 ? kBlue : kYellow;
        std::vector<Blob> blobs;
        AddRobot(pattern, dp.codebook, static_cast<int>(e), team, pose, &blobs);
        detector.Detect(blobs, &detections);
        ASSERT_EQ(detections.size(), 1u) << c.pattern << " entry " << e << " trial " << trial;
        const Detection& d = detections[0];
        EXPECT_EQ(d.status, DetectionStatus::kOk);
        EXPECT_EQ(d.id, dp.codebook.entries[e].id) << c.pattern << " entry " << e;
        EXPECT_EQ(d.team_colour, team);
        EXPECT_LT(d.residual_mm2, 1e-8);       // rounding of E = Sq + Sw - 2 sqrt(.), Sq ~ 2e4 mm^2
        EXPECT_NEAR(d.confidence, 1.0, 1e-5);  // 1 dof (Simple): 1 - Q ~ sqrt(E)
        ExpectPose(d.pose, pose, 1e-9, 1e-11);
        ids_seen.insert(d.id);
      }
    }
    EXPECT_EQ(ids_seen.size(), c.expected_ids) << c.pattern;
  }
}

TEST(Detector, SymmetricPatternWithoutColourCuesIsAmbiguous) {
  for (const char* name : {"linear", "triangle"}) {
    DetectorPattern dp = MakeDetectorPattern(LoadPattern(name), {"pink", "green"});
    Detector detector(MakeConfig({dp}));
    std::vector<Blob> blobs;
    const Pose2 pose{100.0, -50.0, 0.3};
    for (const Patch& patch : dp.pattern.patches) {
      blobs.push_back({pose.Apply(patch.position_mm), patch.role == PatchRole::kKey ? kBlue : kPink,
                       3.14159 * patch.radius_mm * patch.radius_mm});
    }
    std::vector<Detection> detections;
    DetectStats stats;
    detector.Detect(blobs, &detections, &stats);
    ASSERT_EQ(detections.size(), 1u) << name;
    EXPECT_EQ(detections[0].status, DetectionStatus::kAmbiguous) << name;
    EXPECT_EQ(detections[0].id, -1);
    EXPECT_EQ(stats.ambiguous, 1);
    EXPECT_NEAR(detections[0].pose.x_mm, pose.x_mm, 1e-9);  // the position is still known
  }
}

TEST(Detector, ButterflyWithATolerancePastItsAsymmetryIsAmbiguous) {
  // Wrong rotations of the SSL pattern leave E >= 932 mm^2 (hand computed); with patch_sigma_mm =
  // 20 the tolerance (400 * 29.9 mm^2) accepts them all and every colouring is an ID.
  DetectorOptions options;
  options.patch_sigma_mm = 20.0;
  Detector detector(MakeConfig({SslDetectorPattern()}, options));
  std::vector<Blob> blobs;
  const DetectorPattern dp = SslDetectorPattern();
  AddRobot(dp.pattern, dp.codebook, 3, kBlue, Pose2{0, 0, 1.0}, &blobs);
  std::vector<Detection> detections;
  detector.Detect(blobs, &detections);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].status, DetectionStatus::kAmbiguous);
}

TEST(Detector, ButterflyWrongRotationsFailTheDefaultTolerance) {
  // The geometric test alone fixes the SSL pattern's rotation: the best wrong rotation's E is far
  // above the default tolerance, 4 mm^2 * chi2_7(0.9999) = 4 * 29.88 = 119.5 mm^2.
  Detector detector(MakeConfig({SslDetectorPattern()}));
  EXPECT_NEAR(detector.ResidualTolerance(0), 4.0 * 29.8775, 0.01);
}

// Settings that travel: a calibration error moves each blob, and the detector's tolerance takes
// the calibration's recorded residual into account. The VSS two-rectangle robot (key and ID 36 mm
// apart, m = 2, one degree of freedom) seen through a calibration that puts each rectangle 6 mm
// too far out along the key-ID axis: E = (12 mm)^2 / 2 = 72 mm^2 (a two-point rigid fit leaves
// half the squared change of their distance). The shipped tolerance 2^2 * chi2_1^-1(0.9999) =
// 4 * 15.137 = 60.5 mm^2 misses it; with the calibration's residual of 6 mm recorded, sigma^2 =
// 4 + 36 gives 605 mm^2 and the robot is found with its ID.
TEST(Detector, CalibrationResidualWidensTheGeometricTolerance) {
  const DetectorPattern dp =
      MakeDetectorPattern(LoadPattern("vss-two-rectangles"), {"pink", "green"});
  const Pose2 pose{300.0, -200.0, 0.7};
  const std::vector<Blob> blobs = {
      {pose.Apply(dp.pattern.patches[0].position_mm + Vec2(0.0, 6.0)), kBlue, 2240.0},
      {pose.Apply(dp.pattern.patches[1].position_mm - Vec2(0.0, 6.0)), kGreen, 2240.0}};
  DetectorOptions options;  // the shipped numbers: patch_sigma_mm = 2
  Detector ignored(MakeConfig({dp}, options));
  EXPECT_NEAR(ignored.ResidualTolerance(0), 4.0 * 15.1367, 0.01);
  std::vector<Detection> detections;
  ignored.Detect(blobs, &detections);
  EXPECT_TRUE(detections.empty());

  options.calibration_residual_mm = 6.0;
  Detector with(MakeConfig({dp}, options));
  EXPECT_NEAR(with.ResidualTolerance(0), 40.0 * 15.1367, 0.1);
  with.Detect(blobs, &detections);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].status, DetectionStatus::kOk);
  EXPECT_EQ(detections[0].id, dp.codebook.entries[1].id);
  EXPECT_NEAR(detections[0].residual_mm2, 72.0, 1e-6);
  // The confidence uses the same sigma^2: P(chi2_1 >= 72 / 40).
  EXPECT_NEAR(detections[0].confidence, std::erfc(std::sqrt(72.0 / 40.0 / 2.0)), 1e-9);
  ExpectPose(detections[0].pose, pose, 6.0 + 1e-6, 1e-9);  // off by at most one patch's 6 mm
}

TEST(Detector, MissingPatchRejectedOrFittedAndSaidSo) {
  const DetectorPattern dp = SslDetectorPattern();
  const Pose2 pose{-400.0, 250.0, -2.0};
  std::vector<Blob> blobs;
  AddRobot(dp.pattern, dp.codebook, 5, kYellow, pose, &blobs, /*skip_patch=*/3);
  std::vector<Detection> detections;
  Detector reject(MakeConfig({dp}));
  reject.Detect(blobs, &detections);
  EXPECT_TRUE(detections.empty());

  DetectorOptions options;
  options.missing_patch = MissingPatchPolicy::kFit;
  Detector fit(MakeConfig({dp}, options));
  DetectStats stats;
  fit.Detect(blobs, &detections, &stats);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].status, DetectionStatus::kMissingPatch);
  EXPECT_EQ(detections[0].missing_patch, 3);
  EXPECT_EQ(detections[0].blob[3], -1);
  // The missing back-left slot could be pink or green: both are SSL IDs (5 GPPG, 1 GPGP).
  EXPECT_EQ(detections[0].id, -1);
  EXPECT_EQ(stats.missing_fits, 1);
  ExpectPose(detections[0].pose, pose, 1e-9, 1e-11);
}

TEST(Detector, MissingPatchIdFromTheOnlyCompletionInTheCodebook) {
  DetectorPattern dp = SslDetectorPattern();
  // A two-ID codebook: PPGP (0) and GGGG (8). PPGP without its front-left dot reads ?PGP, and of
  // PPGP / GPGP only PPGP is in this book.
  dp.codebook.entries = {SslCodebook().entries[0], SslCodebook().entries[8]};
  DetectorOptions options;
  options.missing_patch = MissingPatchPolicy::kFit;
  Detector detector(MakeConfig({dp}, options));
  std::vector<Blob> blobs;
  AddRobot(dp.pattern, dp.codebook, 0, kBlue, Pose2{10, 20, 0.5}, &blobs, /*skip_patch=*/1);
  std::vector<Detection> detections;
  detector.Detect(blobs, &detections);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].status, DetectionStatus::kMissingPatch);
  EXPECT_EQ(detections[0].id, 0);
}

TEST(Detector, KeyMissingIsNotDetected) {
  const DetectorPattern dp = SslDetectorPattern();
  DetectorOptions options;
  options.missing_patch = MissingPatchPolicy::kFit;
  Detector detector(MakeConfig({dp}, options));
  std::vector<Blob> blobs;
  AddRobot(dp.pattern, dp.codebook, 2, kBlue, Pose2{0, 0, 0}, &blobs, /*skip_patch=*/0);
  std::vector<Detection> detections;
  detector.Detect(blobs, &detections);
  EXPECT_TRUE(detections.empty());
}

TEST(Detector, ExtraBlobsOnAndOffTheRing) {
  const DetectorPattern dp = SslDetectorPattern();
  Detector detector(MakeConfig({dp}));
  const Pose2 pose{300.0, 300.0, 0.7};
  std::vector<Blob> blobs;
  AddRobot(dp.pattern, dp.codebook, 11, kBlue, pose, &blobs);
  // A pink dot on the 65 mm ring straight ahead (between the front dots), a green one at 40 mm
  // and a blue one near by.
  blobs.push_back({pose.Apply(Vec2(65.0, 0.0)), kPink, 1256.0});
  blobs.push_back({pose.Apply(Vec2(0.0, 40.0)), kGreen, 1256.0});
  blobs.push_back({pose.Apply(Vec2(-30.0, 0.0)), kBlue, 400.0});
  std::vector<Detection> detections;
  DetectStats stats;
  detector.Detect(blobs, &detections, &stats);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].id, 11);
  EXPECT_EQ(detections[0].status, DetectionStatus::kOk);
  ExpectPose(detections[0].pose, pose, 1e-9, 1e-11);
  EXPECT_GE(stats.neighbours, 5);  // the extra on-ring dot was a neighbour and was outvoted
}

TEST(Detector, KeyBlobWithNoPatternAndKeyOfWrongSize) {
  const DetectorPattern dp = SslDetectorPattern();
  Detector detector(MakeConfig({dp}));
  std::vector<Blob> blobs = {{Vec2(0, 0), kBlue, 1963.0},
                             {Vec2(65, 0), kPink, 1256.0},
                             {Vec2(0, 65), kGreen, 1256.0},
                             {Vec2(1000, 0), kYellow, 1963.0}};
  std::vector<Detection> detections;
  DetectStats stats;
  detector.Detect(blobs, &detections, &stats);
  EXPECT_TRUE(detections.empty());
  EXPECT_EQ(stats.key_candidates, 2);

  // A real pattern whose key is twice the area_ratio_max too big is no key candidate.
  blobs.clear();
  AddRobot(dp.pattern, dp.codebook, 0, kBlue, Pose2{}, &blobs);
  for (Blob& b : blobs) {
    if (b.colour == kBlue) b.area_mm2 *= 5.0;
  }
  detector.Detect(blobs, &detections, &stats);
  EXPECT_TRUE(detections.empty());
  EXPECT_EQ(stats.key_candidates, 0);
}

TEST(Detector, CrowdedTouchingRobotsWithBlobsNearTwoKeys) {
  // Seven SSL robots in a hexagonal cluster, centres 180 mm apart (touching 90 mm robots), and a
  // reach so wide (65 + 60 mm) that every key sees dots of its neighbours.
  const DetectorPattern dp = SslDetectorPattern();
  DetectorOptions options;
  options.reach_margin_mm = 60.0;
  options.max_neighbours = 16;
  Detector detector(MakeConfig({dp}, options));
  std::vector<Blob> blobs;
  std::vector<Pose2> poses = {{0, 0, 0.1}};
  for (int k = 0; k < 6; ++k) {
    const double a = k * std::numbers::pi / 3.0;
    poses.push_back({180.0 * std::cos(a), 180.0 * std::sin(a), 0.9 * k - 2.0});
  }
  for (int r = 0; r < 7; ++r)
    AddRobot(dp.pattern, dp.codebook, r, r % 2 ? kYellow : kBlue, poses[r], &blobs);
  std::vector<Detection> detections;
  DetectStats stats;
  detector.Detect(blobs, &detections, &stats);
  ASSERT_EQ(detections.size(), 7u);
  for (int r = 0; r < 7; ++r) {
    const auto it = std::find_if(detections.begin(), detections.end(), [&](const Detection& d) {
      return d.id == r && d.team_colour == (r % 2 ? kYellow : kBlue);
    });
    ASSERT_NE(it, detections.end()) << r;
    EXPECT_EQ(it->status, DetectionStatus::kOk);
    ExpectPose(it->pose, poses[r], 1e-9, 1e-11);
  }
  EXPECT_GT(stats.neighbours, 7 * 4);  // foreign dots were in reach
}

TEST(Detector, TwoPatternsShareAKeyColourAndTheLargerFitWins) {
  // Simple and ssl-standard both keyed by blue: a noisy SSL robot also holds four Simple
  // patterns (key + one dot each), whose E is smaller, but the SSL fit explains all five blobs.
  // A lone Simple robot elsewhere is still found as Simple.
  DetectorPattern simple = MakeDetectorPattern(LoadPattern("simple"), {"pink", "green"});
  Detector detector(MakeConfig({SslDetectorPattern(), simple}));
  const DetectorPattern dp = SslDetectorPattern();
  RandomStream rng(5, 0, 0);
  std::vector<Detection> detections;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Blob> blobs;
    AddRobot(dp.pattern, dp.codebook, trial % 16, kBlue, RandomPose(rng, 500.0), &blobs);
    for (Blob& b : blobs) b.position_mm += 0.5 * Vec2(rng.Normal(), rng.Normal());
    AddRobot(simple.pattern, simple.codebook, 1, kBlue, Pose2{2000, 0, 1}, &blobs);
    detector.Detect(blobs, &detections);
    ASSERT_EQ(detections.size(), 2u);
    EXPECT_EQ(detections[0].pattern, 0);
    EXPECT_EQ(detections[0].id, trial % 16);
    EXPECT_EQ(detections[1].pattern, 1);
    EXPECT_EQ(detections[1].id, 1);  // green
  }
}

TEST(Detector, OutputDoesNotDependOnBlobOrder) {
  const DetectorPattern dp = SslDetectorPattern();
  Detector detector(MakeConfig({dp}));
  std::vector<Blob> blobs;
  RandomStream rng(3, 0, 0);
  for (int r = 0; r < 8; ++r) {
    AddRobot(dp.pattern, dp.codebook, r, r < 4 ? kBlue : kYellow,
             Pose2{-1500.0 + 400.0 * r, rng.Uniform(-100, 100), rng.Uniform(-3, 3)}, &blobs);
  }
  std::vector<Detection> a, b;
  detector.Detect(blobs, &a);
  std::reverse(blobs.begin(), blobs.end());
  detector.Detect(blobs, &b);
  ASSERT_EQ(a.size(), 8u);
  ASSERT_EQ(b.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].team_colour, b[i].team_colour);
    EXPECT_EQ(a[i].pose.x_mm, b[i].pose.x_mm);
  }
  // Fixed order: blue before yellow, then by ID.
  EXPECT_EQ(a[0].team_colour, kBlue);
  EXPECT_EQ(a[0].id, 0);
  EXPECT_EQ(a[7].team_colour, kYellow);
  EXPECT_EQ(a[7].id, 7);
}

TEST(Detector, NoisyButterflyMissesAtTheConfiguredRate) {
  // With sigma = patch_sigma_mm, a correct correspondence fails the geometric test with
  // probability 1 - geometry_confidence = 0.01 here. N = 4000: expect 40 misses, sd sqrt(40 *
  // 0.99) = 6.3; accept within 4 sd.
  DetectorOptions options;
  options.patch_sigma_mm = 1.0;
  options.geometry_confidence = 0.99;
  const DetectorPattern dp = SslDetectorPattern();
  Detector detector(MakeConfig({dp}, options));
  RandomStream rng(11, 2, 0);
  int misses = 0, wrong = 0;
  const int n = 4000;
  std::vector<Detection> detections;
  for (int t = 0; t < n; ++t) {
    const Pose2 pose = RandomPose(rng);
    std::vector<Blob> blobs;
    const int entry = static_cast<int>(rng.Below(16));
    AddRobot(dp.pattern, dp.codebook, entry, kBlue, pose, &blobs);
    for (Blob& b : blobs) b.position_mm += Vec2(rng.Normal(), rng.Normal());
    detector.Detect(blobs, &detections);
    if (detections.empty()) {
      ++misses;
    } else if (detections[0].id != entry) {
      ++wrong;
    }
  }
  EXPECT_NEAR(misses, 40.0, 4.0 * 6.3);
  EXPECT_EQ(wrong, 0);
}

TEST(Detector, ConfigurationErrors) {
  auto expect_error = [](DetectorConfig config, const std::string& message) {
    EXPECT_INPUT_ERROR(Detector detector(std::move(config)), message);
  };
  DetectorConfig config = MakeConfig({SslDetectorPattern()});
  config.patterns[0].key_colours = {"purple"};
  expect_error(config, "pattern ssl-standard: key colour \"purple\" is not in the palette");
  config = MakeConfig({SslDetectorPattern()});
  config.options.max_neighbours = 3;
  expect_error(config,
               "pattern ssl-standard: max_neighbours is 3; expected at least 4 (its non-key "
               "patches)");
  config = MakeConfig({SslDetectorPattern()});
  config.options.geometry_confidence = 1.0;
  expect_error(config, "geometry_confidence is 1; expected a probability in (0, 1)");
  config = MakeConfig({SslDetectorPattern()});
  config.palette.push_back("blue");
  expect_error(config, "palette colour \"blue\" is listed twice; expected distinct colour names");
  config = MakeConfig({SslDetectorPattern()});
  config.options.ml.max_iterations = 0;  // the one limit, estimate::Check with prefix "ml_"
  expect_error(config, "ml_max_iterations is 0; expected an integer in [1, 1000]");
}

TEST(DetectorOptions, CheckReportsEveryBrokenConstraint) {
  DetectorOptions options;
  EXPECT_TRUE(Check(options).empty());
  options.calibration_residual_mm = -1.0;
  EXPECT_EQ(Check(options).front().message,
            "calibration_residual_mm is -1; expected a finite number >= 0 (mm)");
  options.calibration_residual_mm = 0.0;
  options.patch_sigma_mm = 0.0;
  options.area_ratio_max = 0.1;  // below area_ratio_min 0.4
  options.ml.max_iterations = 1001;
  const std::vector<OptionsProblem> problems = Check(options);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].field, "patch_sigma_mm");
  EXPECT_EQ(problems[1].message,
            "area_ratio_max is 0.1; expected a finite number > area_ratio_min (0.4)");
  EXPECT_EQ(problems[2].message, "ml_max_iterations is 1001; expected an integer in [1, 1000]");
  EXPECT_INPUT_ERROR(Validate(options), "patch_sigma_mm is 0; expected a finite number > 0 (mm)");
}

TEST(DetectorEnums, NamesRoundTrip) {
  for (const auto& [status, name] : kDetectionStatusNames.entries) {
    EXPECT_EQ(DetectionStatusName(status), name);
    EXPECT_EQ(FindName(name, kDetectionStatusNames), status);
  }
  EXPECT_EQ(MissingPatchPolicyName(MissingPatchPolicy::kFit), "fit");
  EXPECT_EQ(FindName("reject", kMissingPatchPolicyNames), MissingPatchPolicy::kReject);
}

}  // namespace
}  // namespace patlab::detect

namespace patlab::detect {
namespace {

TEST(ChiSquaredSurvival, MatchesKnownValues) {
  // Tabulated chi-square upper tail values: P(chi2_1 >= 3.841459) = 0.05,
  // P(chi2_2 >= 5.991465) = 0.05, P(chi2_7 >= 18.475307) = 0.01, P(chi2_5 >= 1.145476) = 0.95.
  EXPECT_NEAR(ChiSquaredSurvival(1, 3.841459), 0.05, 1e-7);
  EXPECT_NEAR(ChiSquaredSurvival(2, 5.991465), 0.05, 1e-7);
  EXPECT_NEAR(ChiSquaredSurvival(7, 18.475307), 0.01, 1e-7);
  EXPECT_NEAR(ChiSquaredSurvival(5, 1.145476), 0.95, 1e-6);
  EXPECT_DOUBLE_EQ(ChiSquaredSurvival(3, 0.0), 1.0);
}

TEST(Detector, NonFiniteBlobsAreIgnored) {
  DetectorPattern dp;
  dp.pattern = testing::LoadPattern("ssl-standard");
  dp.codebook = GenerateCodebook(dp.pattern, FindSymmetry(dp.pattern, 10.0), {"pink", "green"});
  dp.key_colours = {"blue"};
  Detector detector(testing::MakeConfig({dp}));
  std::vector<Blob> blobs;
  testing::AddRobot(dp.pattern, dp.codebook, 6, testing::kBlue, Pose2{5, 5, 1}, &blobs);
  blobs.push_back({Vec2(std::nan(""), 0.0), testing::kBlue, 1963.0});
  blobs.push_back({Vec2(1e308, -1e308), testing::kPink, 1256.0});
  blobs.push_back({Vec2(-1e308, 1e308), testing::kBlue, 1963.0});
  blobs.push_back({Vec2(std::numeric_limits<double>::infinity(), 0.0), testing::kPink, 1256.0});
  std::vector<Detection> detections;
  detector.Detect(blobs, &detections);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].id, 6);
}

}  // namespace
}  // namespace patlab::detect

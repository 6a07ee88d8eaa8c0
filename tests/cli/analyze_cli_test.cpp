// `patlab analyze` end to end (the real binary, real files), `patlab detect --track`, and the
// chain frames -> detect -> track -> analyze against known truth, here with few frames;
// scripts/analyze_chain.py runs the same chain with 300 frames (results/analyze).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "../test_util.h"
#include "patlab/analysis/analyze.h"
#include "patlab/core/format.h"
#include "patlab/core/geometry.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_results.h"

namespace patlab {
namespace {

using testing::kGolden;
using testing::kPatlab;
using testing::RunCommand;

// Two subjects, 2 runs of 150 frames, white noise; b has a gap at frames 60-64 of run 1.
std::string SmallTrack() {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::string csv = "frame,subject,run,x_mm,y_mm,theta_rad\n";
  for (int run = 1; run <= 2; ++run) {
    for (int f = 0; f < 150; ++f) {
      for (const char* s : {"a", "b"}) {
        if (s[1] == 0 && s[0] == 'b' && run == 1 && f >= 60 && f < 65) continue;
        csv += StringPrintf("%d,%s,%d,%.4f,%.4f,%.5f\n", f, s, run, 3.0 * f + noise(rng),
                            100.0 + noise(rng), 0.01 * noise(rng));
      }
    }
  }
  return csv;
}

TEST(AnalyzeCli, WritesTableTestsErrorsAndManifest) {
  testing::TempDir dir;
  const std::string track = dir.Write("t.csv", SmallTrack());
  const auto r = RunCommand(kPatlab + " analyze " + track + " --out " + dir.Path("out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Run 1 of b: frames 0-59 (60, too short for 2 x 40 + 1) and 65-149 (85, 5 kept); run 2: 70.
  EXPECT_NE(r.err.find("b: skipped 1 segment(s), 60 samples, shorter than 81 frames"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("\nb                  75 "), std::string::npos) << r.err;
  const std::string table = testing::ReadFile(dir.Path("out/analyze.csv"));
  EXPECT_EQ(table.substr(0, table.find('\n')),
            "subject,n,samples,segments,skipped_segments,skipped_samples,sx_mm,sx_lo,sx_hi,"
            "sx_iid_lo,sx_iid_hi,sy_mm,sy_lo,sy_hi,sy_iid_lo,sy_iid_hi,stheta_rad,stheta_lo,"
            "stheta_hi,stheta_iid_lo,stheta_iid_hi,lag1_x,lag1_y,true_sx_mm,true_sx_lo,true_sx_hi,"
            "true_sx_iid_lo,true_sx_iid_hi,true_sy_mm,true_sy_lo,true_sy_hi,true_sy_iid_lo,"
            "true_sy_iid_hi,true_stheta_rad,true_stheta_lo,true_stheta_hi,true_stheta_iid_lo,"
            "true_stheta_iid_hi,true_mean_x_mm,true_mean_y_mm");
  EXPECT_NE(table.find("\na,140,300,2,0,0,"), std::string::npos) << table;
  const std::string tests = testing::ReadFile(dir.Path("out/analyze_tests.csv"));
  EXPECT_NE(tests.find("est,x,a,b,"), std::string::npos) << tests;
  const auto manifest = nlohmann::json::parse(testing::ReadFile(dir.Path("out/analyze.json")));
  EXPECT_EQ(manifest["analysis"]["kernel_radius_samples"], 40);
  EXPECT_EQ(manifest["analysis"]["detrend"], "smooth");
  EXPECT_NE(manifest["analysis"]["std_interval_method"].get<std::string>().find("Bartlett"),
            std::string::npos);
  EXPECT_GE(manifest["subjects"][0]["est"]["x"]["tau"].get<double>(), 1.0);
  EXPECT_NEAR(manifest["analysis"]["white_noise_residual_factor"].get<double>(), 0.97387, 1e-5);
  EXPECT_TRUE(std::filesystem::exists(dir.Path("out/analyze_errors.csv")));
}

// --detrend linear keeps every sample (no kernel radius); an AR(1) track (phi 0.9) warns on
// stderr that the iid interval is too narrow; a misspelt detrending is exit 2 naming the flag.
TEST(AnalyzeCli, DetrendLinearAndTheAutocorrelationWarning) {
  testing::TempDir dir;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, std::sqrt(1.0 - 0.81));
  std::string csv = "frame,x_mm,y_mm\n";
  double ex = 0.0, ey = 0.0;
  for (int f = 0; f < 1000; ++f) {
    ex = 0.9 * ex + noise(rng);
    ey = 0.9 * ey + noise(rng);
    csv += StringPrintf("%d,%.4f,%.4f\n", f, 5.0 * f + ex, ey);
  }
  const std::string track = dir.Write("ar1.csv", csv);
  const auto r =
      RunCommand(kPatlab + " analyze " + track + " --detrend linear -q --out " + dir.Path("out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: subject \"track\", est x: lag-1 autocorrelation 0."),
            std::string::npos)
      << r.err;
  const std::string table = testing::ReadFile(dir.Path("out/analyze.csv"));
  EXPECT_NE(table.find("\ntrack,1000,1000,1,0,0,"), std::string::npos) << table;
  const auto bad =
      RunCommand(kPatlab + " analyze " + track + " --detrend spline --out " + dir.Path("bad"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--detrend"), std::string::npos) << bad.err;
}

TEST(AnalyzeCli, BadInputExitsTwoWithFileLineAndWritesNothing) {
  testing::TempDir dir;
  const std::string track = dir.Write("t.csv", "frame,subject,x_mm,y_mm\n1,a,0,0\n2,a,nan,0\n");
  const auto r = RunCommand(kPatlab + " analyze " + track + " --out " + dir.Path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab analyze: " + track +
                       ":3: column 3 ('x_mm'): 'nan' is not a finite number; "
                       "expected a finite number\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
  const auto none = RunCommand(kPatlab + " analyze --out " + dir.Path("out"));
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_EQ(
      none.err,
      "patlab analyze: no track files; expected 'patlab analyze TRACK.csv...' (see --help)\n");
}

// The golden frame twice: two frames of ten robots, each within the golden test's tolerance of
// its true pose.
TEST(AnalyzeCli, DetectWritesATrackCsvThatAnalyzeReads) {
  testing::TempDir dir;
  const std::string png = kGolden + "ssl-frame.png";
  const auto r = RunCommand(kPatlab + " detect " + png + " " + png + " --thresholds " + kGolden +
                            "ssl-frame.thresholds.toml --calibration " + kGolden +
                            "ssl-frame.calibration.toml --settings " + kGolden +
                            "ssl-frame.detector.toml --out " + dir.Path("d") + " --track");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir.Path("d/detections.csv")));
  const std::vector<analysis::MeasuredTrack> tracks =
      analysis::ReadTrackCsv(dir.Path("d/track.csv"), analysis::TrackColumns{});
  ASSERT_EQ(tracks.size(), 10u);
  EXPECT_EQ(tracks[0].subject, "blue-0");
  EXPECT_EQ(tracks[0].frame, (std::vector<int64_t>{0, 1}));
  EXPECT_NEAR(tracks[0].x[0], -1100.0, 5.0);
  EXPECT_NEAR(tracks[0].y[0], 700.0, 5.0);
  EXPECT_NEAR(tracks[0].theta[0], 0.3, 0.05);
  const auto missing = RunCommand(kPatlab + " detect " + png + " --thresholds " + kGolden +
                                  "ssl-frame.thresholds.toml --calibration " + kGolden +
                                  "ssl-frame.calibration.toml --track --out " + dir.Path("t2"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err,
            "patlab detect: --track needs --settings; expected detector settings naming the "
            "patterns\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("t2")));
}

// --track writes into --out (docs/cli.md), so it needs --out, and the old form --track FILE is
// answered with the new one.
TEST(AnalyzeCli, DetectTrackNeedsOutAndTakesNoFileName) {
  testing::TempDir dir;
  const std::string flags =
      " --thresholds " + kGolden + "ssl-frame.thresholds.toml --calibration " + kGolden +
      "ssl-frame.calibration.toml --settings " + kGolden + "ssl-frame.detector.toml";
  const std::string png = kGolden + "ssl-frame.png";
  const auto no_out = RunCommand(kPatlab + " detect " + png + flags + " --track");
  EXPECT_EQ(no_out.exit_code, 2);
  EXPECT_EQ(no_out.err,
            "patlab detect: --track needs --out; expected --out DIR, where track.csv is written\n");
  EXPECT_TRUE(no_out.out.empty());
  const auto old_form = RunCommand(kPatlab + " detect " + png + flags + " --track " +
                                   dir.Path("t.csv") + " --out " + dir.Path("d"));
  EXPECT_EQ(old_form.exit_code, 2);
  EXPECT_EQ(old_form.err, "patlab detect: --track takes no file name ('" + dir.Path("t.csv") +
                              "' is not a frame); expected --track --out DIR, which writes "
                              "DIR/track.csv\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("d")));
  EXPECT_FALSE(std::filesystem::exists(dir.Path("t.csv")));
}

// The golden scene's camera with its translation moved by (dx, dy) mm: a shaking camera.
camera::CameraModel Jittered(const camera::CameraModel& camera, double dx, double dy) {
  camera::PinholeCamera p = camera.pinhole();
  p.translation_mm.x() += dx;
  p.translation_mm.y() += dy;
  return camera::CameraModel::Pinhole(p);
}

// Frames -> detect -> track -> analyze: 3 robots driving and turning over 40 frames, sensor noise
// with a new seed per frame, camera jitter N(0, 1 mm), one sample per pixel; smoothing sigma = 3
// samples (the minimum segment is 25 frames; 16 kept per robot). The analysed (bias-corrected) std
// of every robot and axis has a 95% interval that overlaps the interval of the true std (detected
// minus true pose), and the two agree within a factor 2 (with 16 samples the intervals are about
// -25%/+55% wide).
TEST(AnalyzeCli, FramesToTracksToAnalysisAgreesWithTheTruth) {
  formats::SceneFile file = formats::LoadSceneFile(kGolden + "ssl-frame.toml");
  vision::FrameDetector frames(formats::LoadThresholds(kGolden + "ssl-frame.thresholds.toml"),
                               formats::LoadCalibration(kGolden + "ssl-frame.calibration.toml"),
                               formats::LoadDetectorSettings(kGolden + "ssl-frame.detector.toml"),
                               {});
  vision::TrackWriter writer(frames);
  const std::vector<render::RobotPlacement> start(file.scene.robots.begin(),
                                                  file.scene.robots.begin() + 3);
  file.scene.ball_mm.reset();
  file.scene.options.supersampling = 1;  // 16x faster than the scene's 4 (the test runs in seconds)
  std::mt19937_64 rng(2003);
  std::normal_distribution<double> jitter(0.0, 1.0);
  std::string truth = "frame,subject,x_mm,y_mm,theta_rad\n";
  for (int f = 0; f < 40; ++f) {
    file.scene.robots = start;
    for (render::RobotPlacement& robot : file.scene.robots) {
      robot.pose.x_mm += 7.0 * f;
      robot.pose.y_mm -= 2.0 * f;
      robot.pose.theta_rad = WrapAngle(robot.pose.theta_rad + 0.02 * f);
      truth += StringPrintf("%d,%s-%d,%.17g,%.17g,%.17g\n", f, robot.team.c_str(), robot.id,
                            robot.pose.x_mm, robot.pose.y_mm, robot.pose.theta_rad);
    }
    file.scene.options.seed = 100 + static_cast<uint64_t>(f);
    const double dx = jitter(rng), dy = jitter(rng);
    const camera::Image image =
        render::RenderScene(file.scene, Jittered(file.calibration.camera, dx, dy));
    writer.Add(f, frames.Detect(image, "frame" + std::to_string(f)));
  }
  const auto tracks = analysis::ParseTrackCsv(writer.Csv(), "track.csv", analysis::TrackColumns{});
  const auto truths = analysis::ParseTrackCsv(truth, "truth.csv", analysis::TrackColumns{});
  ASSERT_EQ(tracks.size(), 3u);
  analysis::AnalyzeOptions options;
  options.smoothing.sigma_samples = 3.0;
  options.correct_bias = true;
  const analysis::AnalyzeReport report = analysis::AnalyzeTracks(tracks, options, &truths);
  for (const analysis::SubjectAnalysis& a : report.subjects) {
    ASSERT_EQ(a.est.x.n, 16u) << a.subject;
    for (const auto& [est, tru] : {std::pair(a.est.x, a.truth.x), std::pair(a.est.y, a.truth.y),
                                   std::pair(a.est.theta, a.truth.theta)}) {
      EXPECT_LE(est.lower, tru.upper) << a.subject << " est " << est.std << " true " << tru.std;
      EXPECT_LE(tru.lower, est.upper) << a.subject << " est " << est.std << " true " << tru.std;
      EXPECT_LT(est.std / tru.std, 2.0) << a.subject;
      EXPECT_GT(est.std / tru.std, 0.5) << a.subject;
    }
  }
}

}  // namespace
}  // namespace patlab

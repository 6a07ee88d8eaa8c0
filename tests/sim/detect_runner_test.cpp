// The detect-mode runner: determinism over thread counts, exact scenes,
// the experiment's noise model reaching the blobs, and replay of one frame.
#include "patlab/sim/detect_runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/replay.h"
#include "patlab/sim/report.h"
#include "patlab/stats/summary.h"
#include "scene_score.h"

namespace patlab::sim {
namespace {

TEST(NoiseModel, PatchErrorAndCommonOffsetFollowTheFormulas) {
  // Per-axis std within 4 standard errors (SE of a std ~ std / sqrt(2n)).
  const int n = 100000;
  auto check = [&](const NoiseModel& model, double sigma, double want_x, double want_y,
                   bool common) {
    std::vector<double> x(n), y(n);
    for (int k = 0; k < n; ++k) {
      RandomStream rng(9, 1, static_cast<uint64_t>(k));
      const Vec2 e = common ? model.CommonOffset(sigma, rng) : model.PatchError(sigma, rng);
      x[k] = e.x();
      y[k] = e.y();
    }
    EXPECT_NEAR(stats::SampleStd(x), want_x, 4 * want_x / std::sqrt(2.0 * n));
    EXPECT_NEAR(stats::SampleStd(y), want_y, 4 * want_y / std::sqrt(2.0 * n));
  };
  NoiseModel anisotropic;
  anisotropic.sigma_y_ratio = 3.0;
  check(anisotropic, 2.0, 2.0, 6.0, false);
  NoiseModel outliers;
  outliers.outlier_probability = 0.1;
  outliers.outlier_sigma_ratio = 10.0;
  // A mixture: variance sigma^2 (0.9 + 0.1 * 100); its std's SE is larger than a Gaussian's,
  // so compare the variance with a generous 4 SE of the mixture (kurtosis ~ 27).
  {
    std::vector<double> x(n);
    for (int k = 0; k < n; ++k) {
      RandomStream rng(9, 2, static_cast<uint64_t>(k));
      x[k] = outliers.PatchError(1.0, rng).x();
    }
    const double var = std::pow(stats::SampleStd(x), 2);
    EXPECT_NEAR(var, 10.9, 4 * 10.9 * std::sqrt(26.0 / n));
  }
  NoiseModel common;
  common.common_sigma_ratio = 0.5;
  check(common, 2.0, 1.0, 1.0, true);
  RandomStream rng(1, 1, 1);
  EXPECT_EQ(NoiseModel{}.CommonOffset(2.0, rng), Vec2::Zero());
  EXPECT_EQ(common.CommonOffset(0.0, rng), Vec2::Zero());
}

// A small detect experiment in a temp dir: Butterfly (2 ID colours, 16 IDs) and Triangle.
class DetectRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"butterfly", "triangle"}) {
      dir_.Write(std::string("patterns/") + name + ".toml",
                 testing::ReadFile(std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name + ".toml"));
    }
    dir_.Write("experiments/det.toml",
               "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"orange\"]\n"
               "[detector]\npatch_sigma_mm = 1.0\n"
               "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n"
               "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"pink\", \"green\", \"cyan\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n");
  }
  Experiment Load(const std::string& extra_detect, const std::string& sigma = "[0, 1, 6]",
                  const std::string& noise = "") {
    return formats::LoadExperimentFile(dir_.Write(
        "experiments/e.toml",
        "name = \"small\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\", \"triangle\"]\n"
        "seed = 5\n[sigma]\nvalues = " +
            sigma + "\n" + noise + "[detect]\nsettings = \"det.toml\"\nframes = 300\n" +
            extra_detect));
  }
  // One triangle point at sigma 2 mm of `frames` frames (more than one block of frames).
  Experiment LoadLong(int64_t frames, const std::string& extra_detect = "") {
    return formats::LoadExperimentFile(dir_.Write(
        "experiments/long.toml",
        "name = \"long\"\ncorrespondence = \"detect\"\npatterns = [\"triangle\"]\nseed = 5\n"
        "[sigma]\nvalues = [2]\n[detect]\nsettings = \"det.toml\"\nframes = " +
            std::to_string(frames) + "\n" + extra_detect));
  }
  testing::TempDir dir_;
};

TEST_F(DetectRunnerTest, IdenticalForAnyThreadCount) {
  const Experiment e = Load(
      "false_blob_rate_per_m2 = [0, 3]\ndetector_sigma = \"matched\"\n"
      "colour_error_probability = 0.02\nmissing_patch_probability = 0.02\n");
  RunOptions options;
  options.threads = 1;
  const std::string one = DetectResultsCsv(e, RunDetectExperiment(e, options));
  options.threads = 2;
  const std::string two = DetectResultsCsv(e, RunDetectExperiment(e, options));
  options.threads = 8;
  const std::string eight = DetectResultsCsv(e, RunDetectExperiment(e, options));
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, eight);
  // Header + 2 patterns x 2 rates x 3 sigmas, pattern-major, then rate, then sigma.
  EXPECT_EQ(std::count(one.begin(), one.end(), '\n'), 1 + 2 * 2 * 3);
  EXPECT_NE(one.find("\nbutterfly,6,3,5,300,3000,isotropic,6,"), std::string::npos) << one;
  EXPECT_NE(one.find("\ntriangle,0,0,6,300,3000,isotropic,1,"), std::string::npos) << one;
}

// A row without its `point` cell (the fourth: the grid index, which --replay uses).
std::string WithoutPointCell(const std::string& row) {
  size_t start = 0;
  for (int k = 0; k < 3; ++k) start = row.find(',', start) + 1;
  return row.substr(0, start) + row.substr(row.find(',', start) + 1);
}

// docs/architecture.md rule 1: frames are keyed by what the point is, so a run over one sigma
// and one false-blob rate of one pattern gives the row of the full sweep (all but the grid
// index), byte for byte.
TEST_F(DetectRunnerTest, AOneSigmaRunEqualsTheCorrespondingRowOfTheFullSweep) {
  const Experiment full = Load("false_blob_rate_per_m2 = [0, 3]\n");
  const std::string full_csv = DetectResultsCsv(full, RunDetectExperiment(full, {}));
  Experiment one = full;
  one.patterns = {full.patterns[1]};
  one.detect.detector_pattern = {full.detect.detector_pattern[1]};
  one.sigmas_mm = {1.0};
  one.detect.false_blob_rates_per_m2 = {3.0};
  const std::string one_csv = DetectResultsCsv(one, RunDetectExperiment(one, {}));
  std::istringstream in(one_csv);
  std::string header, row, extra;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_FALSE(std::getline(in, extra));
  ASSERT_EQ(row.rfind("triangle,1,3,0,", 0), 0u) << row;
  std::istringstream all(full_csv);
  std::string line;
  int matches = 0;
  while (std::getline(all, line)) {
    if (WithoutPointCell(line) == WithoutPointCell(row)) ++matches;
  }
  EXPECT_EQ(matches, 1) << full_csv << "\n" << row;
}

// A codebook file for the Butterfly holding `entries` (names of the ID colours per slot).
std::string CodebookText(const detect::Codebook& c, size_t entries) {
  std::string text = "pattern = \"butterfly\"\ncolours = [\"pink\", \"green\"]\n";
  for (size_t k = 0; k < entries; ++k) {
    text.append("[[id]]\nid = ").append(std::to_string(c.entries[k].id)).append("\nslots = [");
    for (size_t slot = 0; slot < c.entries[k].colour.size(); ++slot) {
      text.append(slot == 0 ? "\"" : ", \"").append(c.colours[c.entries[k].colour[slot]]);
      text.append("\"");
    }
    text.append("]\n");
  }
  return text;
}

// docs/architecture.md rule 1 for the codebook: a detect point's frames are keyed by the content
// of the codebook it uses (robots wear its IDs), not by where it came from. The Butterfly's
// generated codebook and the same IDs read from a codebook file in another directory are one
// point (same key, same row); a codebook of one ID fewer is another point.
TEST_F(DetectRunnerTest, TheCodebooksContentIsPartOfThePointsIdentity) {
  const auto load = [this](const std::string& settings, const std::string& pattern_table) {
    dir_.Write("experiments/" + settings,
               "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"orange\"]\n"
               "[detector]\npatch_sigma_mm = 1.0\n[[pattern]]\npattern = \"butterfly\"\n"
               "key_colours = [\"blue\", \"yellow\"]\n" +
                   pattern_table);
    return formats::LoadExperimentFile(dir_.Write(
        "experiments/cb.toml",
        "name = \"cb\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\"]\nseed = 5\n"
        "[sigma]\nvalues = [3]\n[detect]\nsettings = \"" +
            settings + "\"\nframes = 200\nrobots_per_team = 4\n"));
  };
  const Experiment generated = load("gen.toml", "id_colours = [\"pink\", \"green\"]\n");
  const DetectPoint g = MakeDetectPoint(generated, 0);
  const detect::Codebook& codebook = g.config.patterns[0].codebook;
  ASSERT_EQ(codebook.entries.size(), 16U);
  dir_.Write("codebooks/all.toml", CodebookText(codebook, 16));
  dir_.Write("codebooks/fewer.toml", CodebookText(codebook, 15));
  const Experiment from_file = load("file.toml", "codebook = \"../codebooks/all.toml\"\n");
  const Experiment fewer = load("fewer.toml", "codebook = \"../codebooks/fewer.toml\"\n");

  EXPECT_EQ(MakeDetectPoint(from_file, 0).key, g.key);
  EXPECT_NE(MakeDetectPoint(fewer, 0).key, g.key);
  const std::string csv = DetectResultsCsv(generated, RunDetectExperiment(generated, {}));
  EXPECT_EQ(DetectResultsCsv(from_file, RunDetectExperiment(from_file, {})), csv);
  EXPECT_NE(DetectResultsCsv(fewer, RunDetectExperiment(fewer, {})), csv);
  // Another palette order relabels the blobs (colour errors draw a palette index): another point.
  Experiment reordered = generated;
  std::swap(reordered.detect.detector.palette[4], reordered.detect.detector.palette[5]);
  EXPECT_NE(MakeDetectPoint(reordered, 0).key, g.key);
}

TEST_F(DetectRunnerTest, ExactScenesAreAllDetectedWithTheirIds) {
  const Experiment e = Load("", "[0]");
  const DetectRunResult result = RunDetectExperiment(e, RunOptions{});
  ASSERT_EQ(result.points.size(), 2u);
  EXPECT_EQ(result.total_frames, 600);
  for (const DetectPointResult& p : result.points) {
    SCOPED_TRACE(p.pattern);
    EXPECT_EQ(p.robots, 300 * 10);
    EXPECT_EQ(p.correct, p.robots);
    EXPECT_EQ(p.detection.rate, 1.0);
    EXPECT_EQ(p.wrong_id, 0);
    EXPECT_EQ(p.ambiguous, 0);
    EXPECT_EQ(p.false_positives, 0);
    EXPECT_EQ(p.wrong_id_rate.rate, 0.0);
    EXPECT_LT(p.x.std, 1e-9);
    EXPECT_LT(p.theta.std, 1e-9);
    // All 3000 robots found: the interval is [3000 / (3000 + z^2), 1].
    EXPECT_NEAR(p.detection.lower, 3000 / (3000 + 1.959963984540054 * 1.959963984540054), 1e-12);
    EXPECT_EQ(p.detection.upper, 1.0);
  }
}

TEST_F(DetectRunnerTest, RatesHaveValidIntervals) {
  const Experiment e = Load(
      "false_blob_rate_per_m2 = [0, 5]\ncolour_error_probability = 0.05\n"
      "missing_patch_probability = 0.05\n");
  const DetectRunResult result = RunDetectExperiment(e, RunOptions{});
  ASSERT_EQ(result.points.size(), 2u * 2u * 3u);
  bool some_wrong = false;
  for (const DetectPointResult& p : result.points) {
    EXPECT_EQ(p.robots, p.correct + p.wrong_id + p.unknown_id + p.ambiguous + p.missed);
    for (const stats::Proportion& r : {p.detection, p.wrong_id_rate, p.ambiguous_rate}) {
      EXPECT_LE(0.0, r.lower);
      EXPECT_LE(r.lower, r.rate);
      EXPECT_LE(r.rate, r.upper);
      EXPECT_LE(r.upper, 1.0);
      EXPECT_LT(r.lower, r.upper);
    }
    EXPECT_LE(p.false_positives_per_frame.lower, p.false_positives_per_frame.rate);
    EXPECT_LT(p.false_positives_per_frame.rate, p.false_positives_per_frame.upper);
    if (p.correct >= 2) {
      EXPECT_LE(p.x.std_lower, p.x.std);
      EXPECT_LE(p.x.std, p.x.std_upper);
    }
    some_wrong = some_wrong || p.wrong_id > 0;
    // With missing patches the detection rate is at most P(all patches seen) plus 4 SE.
    const double all_seen = std::pow(0.95, e.patterns[p.pattern_index].size());
    EXPECT_LT(p.detection.rate,
              all_seen + 4 * std::sqrt(all_seen * (1 - all_seen) / static_cast<double>(p.robots)));
  }
  EXPECT_TRUE(some_wrong);  // colour-label errors turn some IDs into others
}

TEST_F(DetectRunnerTest, PoseErrorsFollowTheNoiseModel) {
  // Isotropic sigma = 1: the fast estimator's position std is near its CRLB-scale value; with
  // sigma_y_ratio = 3 the y error grows about three-fold and x does not (the world-frame noise
  // reaches the blobs through NoiseModel::PatchError).
  const std::string anisotropic = "[noise]\nsigma_y_ratio = 3.0\n";
  const Experiment iso = Load("detector_sigma = \"matched\"\n", "[1]");
  const Experiment aniso = Load("detector_sigma = \"matched\"\n", "[1]", anisotropic);
  const DetectPointResult a = RunDetectExperiment(iso, RunOptions{}).points[0];
  const DetectPointResult b = RunDetectExperiment(aniso, RunOptions{}).points[0];
  EXPECT_NEAR(a.x.std / a.y.std, 1.0, 0.15);
  EXPECT_GT(b.y.std / b.x.std, 2.0);
  EXPECT_NEAR(b.x.std, a.x.std, 0.2 * a.x.std);
  // The Butterfly's CRLB per axis at sigma 1 (results/fig5.csv: 0.44931667 mm); the fast
  // estimator is within 20% of it.
  EXPECT_NEAR(a.crlb_position_mm, 0.44931667, 1e-7);
  EXPECT_LT(a.x.std, 1.2 * a.crlb_position_mm);
  EXPECT_TRUE(std::isnan(b.crlb_position_mm));
}

TEST_F(DetectRunnerTest, AFrameReplaysAlone) {
  const Experiment e = Load("false_blob_rate_per_m2 = 2\n");
  const DetectPoint point = MakeDetectPoint(e, 4);
  EXPECT_EQ(point.pattern_index, 1);
  EXPECT_EQ(point.sigma_index, 1);
  EXPECT_EQ(point.sigma_mm, 1.0);
  const detect::Detector detector(point.config);
  const sim::Scene a = GenerateDetectFrame(e, point, detector, 17);
  const sim::Scene b = GenerateDetectFrame(e, point, detector, 17);
  const sim::Scene c = GenerateDetectFrame(e, point, detector, 18);
  ASSERT_EQ(a.blobs.size(), b.blobs.size());
  for (size_t k = 0; k < a.blobs.size(); ++k) {
    EXPECT_EQ(a.blobs[k].position_mm, b.blobs[k].position_mm);
    EXPECT_EQ(a.blobs[k].colour, b.blobs[k].colour);
  }
  EXPECT_NE(a.robots[0].pose.x_mm, c.robots[0].pose.x_mm);
}

TEST_F(DetectRunnerTest, APointOfMoreThanOneBlockOfFramesFoldsItsBlocks) {
  // kStatisticsBlockFrames + 300 frames: two blocks. The reference replays every frame and takes
  // the two-pass statistics of all pose errors at once.
  const Experiment e = LoadLong(kStatisticsBlockFrames + 300, "robots_per_team = 1\n");
  RunOptions options;
  options.threads = 2;
  const DetectRunResult result = RunDetectExperiment(e, options);
  ASSERT_EQ(result.points.size(), 1U);
  const DetectPointResult& r = result.points[0];
  const DetectPoint point = MakeDetectPoint(e, r.point);
  detect::Detector detector(point.config);
  std::vector<detect::Detection> detections;
  std::vector<double> ex, ey, et;
  int64_t correct = 0, robots = 0;
  for (int64_t f = 0; f < e.detect.frames; ++f) {
    const sim::Scene scene = GenerateDetectFrame(e, point, detector, static_cast<uint64_t>(f));
    detector.Detect(scene.blobs, &detections);
    const FrameScore score = sim::ScoreFrame(scene, detections, e.detect.match_radius_mm);
    correct += score.correct;
    robots += score.robots;
    for (const PoseError& pe : score.pose_errors) {
      ex.push_back(pe.dx_mm);
      ey.push_back(pe.dy_mm);
      et.push_back(pe.dtheta_rad);
    }
  }
  EXPECT_EQ(r.frames, e.detect.frames);
  EXPECT_EQ(result.total_frames, e.detect.frames);
  EXPECT_EQ(r.robots, robots);
  EXPECT_EQ(r.correct, correct);
  ASSERT_GT(ex.size(), 2U);
  EXPECT_NEAR(r.x.std, stats::SampleStd(ex), 1e-12 * r.x.std);
  EXPECT_NEAR(r.y.mean, stats::Mean(ey), 1e-12 * r.y.std);
  EXPECT_NEAR(r.theta.std, stats::SampleStd(et), 1e-12 * r.theta.std);
}

TEST_F(DetectRunnerTest, ShardsOfPointsOfMoreThanOneBlockOfFramesHoldTheirBlocks) {
  // Trial-range shares (docs/merge.md): a point of two blocks of frames, share 2/2 runs block 1
  // only (frames 16384 .. 16393) and returns it unfinished, with its point's header, for the
  // merge; share 1/2 returns block 0. Their blocks finish to the unsharded point.
  const Experiment e = LoadLong(kStatisticsBlockFrames + 10, "robots_per_team = 1\n");
  RunOptions options;
  options.shard = ShardSpec{2, 2};
  const DetectRunResult second = RunDetectExperiment(e, options);
  EXPECT_TRUE(second.points.empty());
  EXPECT_EQ(second.total_frames, 10);
  ASSERT_EQ(second.blocks.size(), 1U);
  ASSERT_EQ(second.block_headers.size(), 1U);
  const WorkBlock& w = second.blocks[0].work;
  EXPECT_EQ(w.point, 0);
  EXPECT_EQ(w.block, 1);
  EXPECT_EQ(w.first, kStatisticsBlockFrames);
  EXPECT_EQ(w.count, 10);
  EXPECT_EQ(second.blocks[0].robots, 20);  // two teams of one robot, ten frames
  EXPECT_EQ(second.block_headers[0].frames, kStatisticsBlockFrames + 10);
  EXPECT_EQ(second.block_headers[0].robots, 0);  // a header carries no counts

  options.shard = ShardSpec{1, 2};
  const DetectRunResult first = RunDetectExperiment(e, options);
  ASSERT_EQ(first.blocks.size(), 1U);
  const DetectBlock both[] = {first.blocks[0], second.blocks[0]};
  const DetectPointResult merged = FinishDetectPoint(first.block_headers[0], both);
  const DetectRunResult whole = RunDetectExperiment(e, {});
  ASSERT_EQ(whole.points.size(), 1U);
  DetectRunResult one;
  one.points = {merged};
  EXPECT_EQ(DetectResultsCsv(e, one), DetectResultsCsv(e, whole));
}

TEST_F(DetectRunnerTest, ReplayedFramesAddUpToTheRunnersCounts) {
  // Every frame the runner scored is the frame GenerateDetectFrame replays (docs/architecture.md
  // rule 3).
  const Experiment e = Load(
      "false_blob_rate_per_m2 = 3\ncolour_error_probability = 0.03\n"
      "missing_patch_probability = 0.03\n",
      "[2]");
  RunOptions options;
  options.threads = 2;
  const DetectRunResult result = RunDetectExperiment(e, options);
  for (const DetectPointResult& r : result.points) {
    const DetectPoint point = MakeDetectPoint(e, r.point);
    detect::Detector detector(point.config);
    sim::DetectionScore sum;
    std::vector<detect::Detection> detections;
    for (int64_t f = 0; f < e.detect.frames; ++f) {
      const sim::Scene scene = GenerateDetectFrame(e, point, detector, static_cast<uint64_t>(f));
      detector.Detect(scene.blobs, &detections);
      sum.Add(sim::ScoreFrame(scene, detections, e.detect.match_radius_mm));
    }
    EXPECT_EQ(sum.correct, r.correct);
    EXPECT_EQ(sum.wrong_id, r.wrong_id);
    EXPECT_EQ(sum.missed, r.missed);
    EXPECT_EQ(sum.false_positives, r.false_positives);
    EXPECT_GT(r.wrong_id + r.missed, 0);  // the frames are not trivial
  }
}

TEST_F(DetectRunnerTest, ReplayDetectFrameScoresWhatTheRunnerScored) {
  // The library replay behind `patlab simulate --replay` (sim/replay.h) is the runner's frame.
  const Experiment e = Load("false_blob_rate_per_m2 = 3\ncolour_error_probability = 0.03\n", "[2]");
  const DetectRunResult result = RunDetectExperiment(e, RunOptions{});
  for (const DetectPointResult& r : result.points) {
    int64_t correct = 0, false_positives = 0;
    for (int64_t f = 0; f < e.detect.frames; ++f) {
      const FrameReplay replay = ReplayDetectFrame(e, {r.point, f, ""});
      correct += replay.score.correct;
      false_positives += replay.score.false_positives;
    }
    EXPECT_EQ(correct, r.correct);
    EXPECT_EQ(false_positives, r.false_positives);
  }
  EXPECT_INPUT_ERROR(ReplayDetectFrame(e, ParseReplayIndex("0,999999", "FRAME")),
                     "--replay 0,999999 is out of range; expected POINT < 2 and FRAME < " +
                         std::to_string(e.detect.frames));
}

}  // namespace
}  // namespace patlab::sim

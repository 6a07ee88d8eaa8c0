// Tests of the section II track experiment (src/patlab/analysis/track.h).
#include "patlab/analysis/track.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "../frame_test_util.h"
#include "patlab/core/rng.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/track_file.h"
#include "patlab/stats/smoothing.h"
#include "patlab/stats/summary.h"

namespace patlab::analysis {
namespace {

// A small, fast experiment: 2 runs of 160 frames, three discs.
TrackOptions Small() {
  TrackOptions o;
  o.runs = 2;
  o.samples_per_run = 160;
  o.trim_samples = 20;
  return o;
}

// Small() with intensity noise, camera jitter and the butterfly pattern as a fourth subject.
TrackOptions NoisyWithButterfly() {
  TrackOptions o = Small();
  o.pixel_sigma = 12.0;
  o.jitter_sigma_px = 0.1;
  o.pattern_file = std::string(PATLAB_SOURCE_DIR) + "/patterns/butterfly.toml";
  o.pattern = formats::LoadPatternFile(o.pattern_file);
  return o;
}

TEST(Track, DefaultsAreValidAndDescribeThePaperSetup) {
  const TrackOptions o;
  EXPECT_TRUE(Check(o).empty());
  // ~4.4 mm/px: the 2.8 m field across 640 px from 3 m.
  EXPECT_NEAR(MmPerPixel(o), 4.373, 0.001);
}

TEST(Track, StaticDiscGivesAConstantTrack) {
  TrackOptions o = Small();
  o.runs = 1;
  o.speed_mm_per_s = 0.0;
  const TrackResult r = RunTrack(o);
  ASSERT_EQ(r.subjects.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const SubjectRun& run = r.data[k][0];
    ASSERT_EQ(run.sample.size(), 160u - 2 * 20);
    EXPECT_EQ(run.missed_frames, 0);
    for (size_t i = 0; i < run.sample.size(); ++i) {
      EXPECT_NEAR(run.est_x_mm[i], 0.0, 1e-9);
      EXPECT_NEAR(run.est_y_mm[i], 0.0, 1e-9);
      EXPECT_EQ(run.true_x_mm[i], run.true_x_mm[0]);
      EXPECT_EQ(run.true_y_mm[i], run.true_y_mm[0]);
    }
    // The constant offset is the quantisation bias of one sub-pixel position: under half a pixel.
    EXPECT_LT(std::abs(run.true_x_mm[0]), 0.5 * MmPerPixel(o));
    EXPECT_LT(std::abs(run.true_y_mm[0]), 0.5 * MmPerPixel(o));
  }
}

TEST(Track, NoiseFreeMovingDiscErrorsStayWellBelowHalfAPixel) {
  const TrackOptions o = Small();
  const TrackResult r = RunTrack(o);
  double worst = 0.0;
  for (const auto& subject : r.data) {
    for (const SubjectRun& run : subject) {
      for (size_t i = 0; i < run.sample.size(); ++i) {
        worst = std::max({worst, std::abs(run.true_x_mm[i]), std::abs(run.true_y_mm[i])});
      }
    }
  }
  EXPECT_GT(worst, 0.0);                  // quantisation is there...
  EXPECT_LT(worst, 0.4 * MmPerPixel(o));  // ...but a 9-14 px disc is good to 0.4 px
}

TEST(Track, MeasureDiscFindsTheDiscWithinQuantisation) {
  const TrackOptions o;
  Vec2 measured;
  ASSERT_TRUE(MeasureDisc(o, 0, 0, Vec2(123.4, -56.7), 50.0, &measured));
  EXPECT_NEAR(measured.x(), 123.4, 0.3 * MmPerPixel(o));
  EXPECT_NEAR(measured.y(), -56.7, 0.3 * MmPerPixel(o));
}

TEST(Track, ResultsAreIdenticalForAnyThreadCount) {
  TrackOptions o = NoisyWithButterfly();
  const TrackResult one = RunTrack(o, {.threads = 1});
  const TrackResult three = RunTrack(o, {.threads = 3});
  ASSERT_EQ(one.subjects.size(), 4u);
  EXPECT_EQ(one.subjects.back(), "butterfly");
  for (size_t k = 0; k < one.subjects.size(); ++k) {
    for (int run = 0; run < o.runs; ++run) {
      EXPECT_EQ(one.data[k][run].est_x_mm, three.data[k][run].est_x_mm);
      EXPECT_EQ(one.data[k][run].true_y_mm, three.data[k][run].true_y_mm);
      EXPECT_EQ(one.data[k][run].true_theta_rad, three.data[k][run].true_theta_rad);
    }
  }
  EXPECT_FALSE(one.data[3][0].true_theta_rad.empty());
  // A different seed gives different noise.
  o.seed += 1;
  const TrackResult other = RunTrack(o, {.threads = 2});
  EXPECT_NE(one.data[0][0].true_x_mm, other.data[0][0].true_x_mm);
}

// docs/architecture.md rule 1: a run's frames are keyed by (seed, run, frame, pixel), so the
// runs of a shorter experiment are the first runs of a longer one, sample for sample.
TEST(Track, TheRunsOfAShorterExperimentAreTheFirstRunsOfALongerOne) {
  TrackOptions two = NoisyWithButterfly();
  TrackOptions three = two;
  three.runs = 3;
  const TrackResult a = RunTrack(two, {.threads = 2});
  const TrackResult b = RunTrack(three, {.threads = 2});
  ASSERT_EQ(a.subjects, b.subjects);
  for (size_t k = 0; k < a.subjects.size(); ++k) {
    for (int run = 0; run < two.runs; ++run) {
      EXPECT_EQ(a.data[k][run].true_x_mm, b.data[k][run].true_x_mm);
      EXPECT_EQ(a.data[k][run].est_y_mm, b.data[k][run].est_y_mm);
      EXPECT_EQ(a.data[k][run].true_theta_rad, b.data[k][run].true_theta_rad);
    }
  }
}

TEST(Track, NoiseRaisesTheErrorAndJitterIsCommonToTheSubjects) {
  TrackOptions o = Small();
  const std::vector<TableRow> clean = MakeTable(RunTrack(o));
  o.jitter_sigma_px = 0.2;
  const TrackResult jittered = RunTrack(o);
  const std::vector<TableRow> noisy = MakeTable(jittered);
  for (size_t k = 0; k < clean.size(); ++k) EXPECT_GT(noisy[k].true_x.std, clean[k].true_x.std);
  // The same frame shift moves every disc: their true errors are strongly correlated.
  const auto& a = jittered.data[0][0].true_x_mm;
  const auto& b = jittered.data[2][0].true_x_mm;
  const double ma = stats::Mean(a), mb = stats::Mean(b);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  EXPECT_GT(sab / std::sqrt(saa * sbb), 0.7);
}

TEST(Track, TableAndTestsHaveOneRowPerSubjectAndPair) {
  const TrackResult r = RunTrack(Small());
  const std::vector<TableRow> table = MakeTable(r);
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(table[0].subject, "40mm");
  EXPECT_EQ(table[0].est_x.n, 2u * 120u);
  EXPECT_LT(table[0].est_x.lower, table[0].est_x.std);
  EXPECT_GT(table[0].est_x.upper, table[0].est_x.std);
  const std::vector<SizeTest> tests = MakeSizeTests(r);
  // {est, true} x {x, y, xy} x {40-50, 40-60, 50-60}.
  ASSERT_EQ(tests.size(), 18u);
  EXPECT_EQ(tests[0].error, "est");
  EXPECT_EQ(tests[0].axis, "x");
  EXPECT_EQ(tests[0].a, "40mm");
  EXPECT_EQ(tests[0].b, "50mm");
  EXPECT_EQ(tests[0].result.n, 240u);
  const std::string csv = TableCsv(table);
  EXPECT_EQ(csv.rfind("subject,n,est_sx_mm,est_sx_lo,est_sx_hi,", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  const std::string errors = ErrorsCsv(Small(), r, 4);
  // 120 kept samples per run: samples 0, 1, 4, 5, ... (adjacent pairs).
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1 + 3 * 2 * 60);
}

TEST(Track, AnySampleCanBeReplayedAlone) {
  TrackOptions o = NoisyWithButterfly();
  const TrackResult r = RunTrack(o);
  ASSERT_EQ(NumSubjects(o), 4);
  for (int k : {0, 3}) {
    const SubjectRun& run = r.data[k][1];
    const size_t i = 37;
    const int frame = run.sample[i];
    Pose2 measured;
    ASSERT_TRUE(MeasureSubject(o, 1, frame, k, &measured));
    const Pose2 truth = TruthPose(o, r.setups[1], frame, k);
    const double h = r.setups[1].heading_rad;
    const double ex = measured.x_mm - truth.x_mm, ey = measured.y_mm - truth.y_mm;
    EXPECT_DOUBLE_EQ(std::cos(h) * ex + std::sin(h) * ey, run.true_x_mm[i]);
    EXPECT_DOUBLE_EQ(-std::sin(h) * ex + std::cos(h) * ey, run.true_y_mm[i]);
  }
}

TEST(Track, RunSetupsComeFromTheRunIdentity) {
  const TrackOptions o;
  const RunSetup a = MakeRunSetup(o, 3), b = MakeRunSetup(o, 3), c = MakeRunSetup(o, 4);
  EXPECT_EQ(a.heading_rad, b.heading_rad);
  EXPECT_EQ(a.start_mm, b.start_mm);
  EXPECT_NE(a.heading_rad, c.heading_rad);
  EXPECT_LE(std::abs(a.heading_rad), o.heading_max_deg * std::numbers::pi / 180.0);
}

TEST(Track, ReplayFrameAgreesWithTheRun) {
  TrackOptions o = NoisyWithButterfly();
  const TrackResult r = RunTrack(o);
  const size_t i = 11;
  const int frame = r.data[0][1].sample[i];
  const std::vector<ReplayedSubject> replay = ReplayFrame(o, 1, frame);
  ASSERT_EQ(replay.size(), 4u);
  for (size_t k = 0; k < replay.size(); ++k) {
    SCOPED_TRACE(k);
    const SubjectRun& run = r.data[k][1];
    ASSERT_EQ(run.sample[i], frame);
    EXPECT_EQ(replay[k].name, r.subjects[k]);
    ASSERT_TRUE(replay[k].found);
    EXPECT_DOUBLE_EQ(replay[k].true_error_mm.x(), run.true_x_mm[i]);
    EXPECT_DOUBLE_EQ(replay[k].true_error_mm.y(), run.true_y_mm[i]);
    EXPECT_EQ(replay[k].has_theta, k == 3);
  }
  EXPECT_DOUBLE_EQ(replay[3].true_theta_error_rad, r.data[3][1].true_theta_rad[i]);
}

TEST(Track, SubjectsAreNamedByDiameterThenPattern) {
  TrackOptions o;
  o.diameters_mm = {40.0, 45.5};
  EXPECT_EQ(SubjectNames(o), (std::vector<std::string>{"40mm", "45.5mm"}));
  EXPECT_EQ(NumSubjects(o), 2);
  EXPECT_DOUBLE_EQ(SubjectOffsetMm(o, 0), -0.5 * o.spacing_mm);
  const Vec2 along = ToTrackFrame(Vec2(1.0, 1.0), std::numbers::pi / 4);
  EXPECT_NEAR(along.x(), std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(along.y(), 0.0, 1e-15);
}

TEST(Track, ManifestRecordsOptionsTableAndOutputs) {
  const TrackOptions o = Small();
  const TrackResult r = RunTrack(o);
  const std::vector<TableRow> table = MakeTable(r);
  const auto j = nlohmann::json::parse(TrackManifestJson(o, r, table, {"out/a.csv"}));
  EXPECT_FALSE(j.contains("command_line"));
  EXPECT_FALSE(j.contains("timings_s"));
  EXPECT_EQ(j.at("platform").at("samples_per_run"), 160);
  EXPECT_EQ(j.at("run_setups").size(), 2u);
  EXPECT_EQ(j.at("table").size(), 3u);
  EXPECT_EQ(j.at("table")[0].at("est_x").at("n"), table[0].est_x.n);
  EXPECT_EQ(j.at("outputs"), nlohmann::json::array({"a.csv"}));
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  EXPECT_EQ(j.at("analysis").at("white_noise_residual_factor").get<double>(),
            stats::ResidualStdFactor(smoothing));
}

TEST(TrackOptions, CheckNamesEveryBrokenFieldAndTheGeometryOnlyOfValidFields) {
  TrackOptions o;
  o.runs = 0;
  o.rate_hz = 0.0;
  o.pixel_sigma = -1.0;
  o.spacing_mm = 40.0;  // neighbours touch, but that is checked only once the fields are valid
  std::vector<std::string> fields;
  for (const OptionsProblem& p : Check(o)) fields.push_back(p.field);
  EXPECT_EQ(fields, (std::vector<std::string>{"runs", "platform.rate_hz", "noise.pixel_sigma"}));
  o.runs = 5;
  o.rate_hz = 30.0;
  o.pixel_sigma = 0.0;
  const std::vector<OptionsProblem> geometry = Check(o);
  ASSERT_EQ(geometry.size(), 1u);
  EXPECT_EQ(geometry[0].field, "platform.spacing_mm");
  o.camera.image_width_px = 8;
  EXPECT_INPUT_ERROR(Validate(o),
                     "camera.image_size_px has 8; expected two integers in [16, 20000] (width, "
                     "height)");
  o = TrackOptions();
  o.patch_level = 30;
  EXPECT_INPUT_ERROR(Validate(o),
                     "render.patch_level is 30; expected an integer in [41, 255] (white patches on "
                     "a darker floor, above background_level)");
}

TrackOptions Parse(const std::string& text) {
  return formats::ParseTrackExperiment(text, "t.toml");
}

TEST(TrackExperiment, ParsesEveryKey) {
  const TrackOptions o = formats::ParseTrackExperiment(
      "name = \"x\"\nseed = 9\nruns = 3\ndiameters_mm = [30, 45.5]\n"
      "[platform]\nsamples_per_run = 500\nrate_hz = 25\nspeed_mm_per_s = 10\nheading_max_deg = 1\n"
      "lateral_range_mm = 100\nstart_jitter_mm = 5\nspacing_mm = 120\nplane_height_mm = 50\n"
      "[camera]\nheight_mm = 2500\nimage_size_px = [800, 600]\nfocal_length_px = 700\n"
      "[render]\nbackground_level = 20\npatch_level = 200\nthreshold_level = 100\n"
      "supersampling = 4\n[noise]\npixel_sigma = 3\njitter_sigma_px = 0.05\n"
      "[analysis]\nsmoothing_sigma_samples = 8\ntrim_samples = 32\n",
      "t.toml");
  EXPECT_EQ(o.name, "x");
  EXPECT_EQ(o.seed, 9u);
  EXPECT_EQ(o.runs, 3);
  EXPECT_EQ(o.diameters_mm, (std::vector<double>{30, 45.5}));
  EXPECT_EQ(o.samples_per_run, 500);
  EXPECT_EQ(o.rate_hz, 25);
  EXPECT_EQ(o.speed_mm_per_s, 10);
  EXPECT_EQ(o.heading_max_deg, 1);
  EXPECT_EQ(o.lateral_range_mm, 100);
  EXPECT_EQ(o.start_jitter_mm, 5);
  EXPECT_EQ(o.spacing_mm, 120);
  EXPECT_EQ(o.plane_height_mm, 50);
  EXPECT_EQ(o.camera.height_mm, 2500);
  EXPECT_EQ(o.camera.image_width_px, 800);
  EXPECT_EQ(o.camera.image_height_px, 600);
  EXPECT_EQ(o.camera.focal_length_px, 700);
  EXPECT_EQ(o.background_level, 20);
  EXPECT_EQ(o.patch_level, 200);
  EXPECT_EQ(o.threshold_level, 100);
  EXPECT_EQ(o.supersampling, 4);
  EXPECT_EQ(o.pixel_sigma, 3);
  EXPECT_EQ(o.jitter_sigma_px, 0.05);
  EXPECT_EQ(o.smoothing_sigma_samples, 8);
  EXPECT_EQ(o.trim_samples, 32);
}

TEST(TrackExperiment, ShippedTable1FileLoads) {
  const TrackOptions o =
      formats::LoadTrackExperiment(std::string(PATLAB_SOURCE_DIR) + "/experiments/table1.toml");
  EXPECT_EQ(o.diameters_mm, (std::vector<double>{40, 50, 60}));
  EXPECT_EQ(o.runs, 5);
  EXPECT_EQ(o.samples_per_run, 2570);
  EXPECT_EQ(o.pattern.name, "butterfly");
}

TEST(TrackExperiment, BadFilesNameTheLineAndWhatIsExpected) {
  EXPECT_INPUT_ERROR(Parse("runs = 0\n"), "t.toml:1: runs is 0; expected an integer in [1, 1000]");
  EXPECT_INPUT_ERROR(
      Parse("seed = 1\nradius = 3\n"),
      "t.toml:2: unknown key 'radius'; expected one of: name, description, seed, runs, "
      "diameters_mm, pattern, patterns_dir, platform, camera, render, noise, analysis");
  EXPECT_INPUT_ERROR(Parse("diameters_mm = [40, \"big\"]\n"),
                     "t.toml:1: diameters_mm contains a string; expected numbers (mm)");
  EXPECT_INPUT_ERROR(Parse("diameters_mm = [40, -5]\n"),
                     "t.toml:1: diameters_mm has -5; expected diameters > 0 (mm)");
  EXPECT_INPUT_ERROR(Parse("diameters_mm = [40, 40]\n"),
                     "t.toml:1: diameters_mm lists 40 twice; expected distinct diameters");
  EXPECT_INPUT_ERROR(
      Parse("\n[noise]\npixel_sigma = -1\n"),
      "t.toml:3: noise.pixel_sigma is -1; expected a finite number >= 0 (grey levels)");
  EXPECT_INPUT_ERROR(Parse("[noise]\njitter_px = 1\n"),
                     "t.toml:2: unknown key 'jitter_px' in [noise]; expected one of: pixel_sigma, "
                     "jitter_sigma_px");
  EXPECT_INPUT_ERROR(
      Parse("[render]\nthreshold_level = 30\n"),
      "t.toml:2: render.threshold_level is 30; expected an integer in [41, 230] (above "
      "background_level, at most patch_level)");
  EXPECT_INPUT_ERROR(
      Parse("[platform]\nsamples_per_run = 50\n"),
      "t.toml:2: platform.samples_per_run is 50; expected an integer in [83, 1000000] "
      "(2 trim_samples + 3 or more)");
  EXPECT_INPUT_ERROR(Parse("[platform]\nspacing_mm = 40\n"),
                     "t.toml:2: platform.spacing_mm is 40; expected more than 53.75 mm so that "
                     "neighbouring subjects do not touch");
  EXPECT_INPUT_ERROR(
      Parse("[platform]\nspeed_mm_per_s = 40\n"),
      "t.toml:1: the track does not fit in the image: subjects reach +-1789.8 x +-361.64 mm "
      "from the image centre but the view is +-1397.2 x +-1047.4 mm; expected a shorter "
      "track (samples_per_run, speed_mm_per_s), a smaller lateral_range_mm, spacing_mm or "
      "heading_max_deg, or a larger image");
  EXPECT_INPUT_ERROR(
      Parse("[camera]\nimage_size_px = [640]\n"),
      "t.toml:2: image_size_px in [camera] is not two integers; expected [width, height] "
      "(px)");
  EXPECT_INPUT_ERROR(Parse("camera = 3\n"),
                     "t.toml:1: camera is an integer; expected a table [camera]");
  EXPECT_INPUT_ERROR_STARTS_WITH(
      Parse("pattern = \"no-such-pattern\"\npatterns_dir = \"/nonexistent\"\n"),
      "t.toml:1: pattern 'no-such-pattern' not found; expected a pattern file path or a name in ");
  // A syntax error, reported with its line.
  EXPECT_INPUT_ERROR_STARTS_WITH(Parse("runs = [\n"), "t.toml:");
}

TEST(TrackExperiment, ValidateNamesTheField) {
  TrackOptions o;
  o.supersampling = 0;
  EXPECT_INPUT_ERROR(Validate(o), "render.supersampling is 0; expected an integer in [1, 32]");
  o = TrackOptions();
  o.smoothing_sigma_samples = 0;
  EXPECT_INPUT_ERROR(RunTrack(o),
                     "analysis.smoothing_sigma_samples is 0; expected a number in (0, 10000] "
                     "(samples)");
}

}  // namespace
}  // namespace patlab::analysis

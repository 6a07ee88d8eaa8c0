// The section-II analysis of measured tracks (analysis/analyze.h): the residual estimator's bias
// against its analytic value, gaps, orientation wrap, the along-travel frame, the truth, the
// paired tests, and every bad input word for word.
#include "patlab/analysis/analyze.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>

#include "../expect_error.h"
#include "patlab/core/geometry.h"

namespace patlab::analysis {
namespace {

// A straight track at `speed` mm/frame along `heading`, with iid N(0, s^2) noise on x and y, for
// the given frame numbers.
MeasuredTrack Line(const std::string& subject, const std::vector<int64_t>& frames, double s,
                   uint32_t seed, double heading = 0.3, double speed = 2.5) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, s);
  MeasuredTrack t;
  t.subject = subject;
  t.run = "r";
  t.file = "t.csv";
  t.first_line = 2;
  for (const int64_t f : frames) {
    t.frame.push_back(f);
    t.x.push_back(speed * static_cast<double>(f) * std::cos(heading) + noise(rng));
    t.y.push_back(speed * static_cast<double>(f) * std::sin(heading) + noise(rng));
  }
  return t;
}

std::vector<int64_t> Range(int64_t lo, int64_t hi) {
  std::vector<int64_t> v;
  for (int64_t f = lo; f < hi; ++f) v.push_back(f);
  return v;
}

// The residual factor and the white-noise lag correlation against numpy, computed independently
// (the full kernel c = delta - w, np.correlate(c, c)):
//   s=10, R=40: sqrt(sum c^2) = 0.9738684893235854, rho_1 = -0.05404003558359275,
//               rho_2 = -0.05301543045992419;  s=3, R=12: 0.9099823423894111, -0.19338417221446055
TEST(Analyze, ResidualFactorAndLagCorrelationMatchTheAnalyticValues) {
  stats::SmoothingOptions s10;
  EXPECT_NEAR(stats::ResidualStdFactor(s10), 0.9738684893235854, 1e-13);
  EXPECT_NEAR(stats::ResidualAutocorrelation(s10, 1), -0.05404003558359275, 1e-13);
  EXPECT_NEAR(stats::ResidualAutocorrelation(s10, 2), -0.05301543045992419, 1e-13);
  EXPECT_DOUBLE_EQ(stats::ResidualAutocorrelation(s10, 0), 1.0);
  stats::SmoothingOptions s3;
  s3.sigma_samples = 3.0;
  EXPECT_NEAR(stats::ResidualStdFactor(s3), 0.9099823423894111, 1e-13);
  EXPECT_NEAR(stats::ResidualAutocorrelation(s3, 1), -0.19338417221446055, 1e-13);
}

// 4 runs x 25,000 samples of white noise, std 1: the estimate is 0.974 of the truth, inside its
// 95% interval (+-0.4% at n ~ 1e5); --correct-bias puts 1 inside it; the lag-1 correlation is the
// analytic -0.054 (its standard error ~ 1 / sqrt(25,000) = 0.006 per run, 0.003 over 4).
TEST(Analyze, WhiteNoiseGivesTheAnalyticBiasAndCorrectBiasRemovesIt) {
  std::vector<MeasuredTrack> tracks;
  for (int run = 0; run < 4; ++run) {
    tracks.push_back(Line("a", Range(0, 25000), 1.0, 100 + run));
    tracks.back().run = "run" + std::to_string(run);
  }
  AnalyzeOptions options;
  const AnalyzeReport plain = AnalyzeTracks(tracks, options);
  ASSERT_EQ(plain.subjects.size(), 1u);
  const SubjectAnalysis& a = plain.subjects[0];
  EXPECT_EQ(a.est.x.n, 4u * (25000 - 80));
  EXPECT_EQ(plain.radius, 40);
  EXPECT_LT(a.est.x.lower, 0.97387);
  EXPECT_GT(a.est.x.upper, 0.97387);
  EXPECT_LT(a.est.y.lower, 0.97387);
  EXPECT_GT(a.est.y.upper, 0.97387);
  EXPECT_GT(a.est.x.upper, 0.9);
  EXPECT_LT(a.est.x.upper, 0.99);  // the bias is visible: 1 is outside the interval
  EXPECT_NEAR(a.est.lag_x, -0.05404, 0.01);
  EXPECT_NEAR(plain.white_noise_lag, -0.05404, 1e-4);
  options.correct_bias = true;
  const SubjectAnalysis c = AnalyzeTracks(tracks, options).subjects[0];
  EXPECT_LT(c.est.x.lower, 1.0);
  EXPECT_GT(c.est.x.upper, 1.0);
  EXPECT_DOUBLE_EQ(c.est.x.std, a.est.x.std / plain.residual_factor);
}

// Frames 0-99, a gap, 150-189 (40 frames: too short for sigma = 10, skipped), a gap, 300-499 with
// the whole track displaced by 1 m after each gap: smoothing across a gap would put the 1 m jump
// into the residuals. Each analysed segment's residuals are those of the segment alone.
TEST(Analyze, SplitsAtGapsSkipsShortSegmentsAndNeverSmoothsAcrossAGap) {
  std::vector<int64_t> frames = Range(0, 100);
  for (int64_t f : Range(150, 190)) frames.push_back(f);
  for (int64_t f : Range(300, 500)) frames.push_back(f);
  MeasuredTrack t = Line("a", frames, 0.5, 7);
  for (size_t i = 100; i < t.x.size(); ++i) t.x[i] += i < 140 ? 1000.0 : 2000.0;
  const AnalyzeReport r = AnalyzeTracks({t}, AnalyzeOptions{});
  const SubjectAnalysis& a = r.subjects[0];
  EXPECT_EQ(a.samples, 340u);
  EXPECT_EQ(a.segments, 2);
  EXPECT_EQ(a.skipped_segments, 1);
  EXPECT_EQ(a.skipped_samples, 40u);
  ASSERT_EQ(a.est_errors.size(), 2u);
  EXPECT_EQ(a.est_errors[0].frame.front(), 40);
  EXPECT_EQ(a.est_errors[0].frame.back(), 59);
  EXPECT_EQ(a.est_errors[1].frame.front(), 340);
  EXPECT_EQ(a.est_errors[1].frame.back(), 459);
  const std::vector<double> alone =
      stats::SmoothingResiduals(std::span<const double>(t.x).subspan(140, 200));
  for (size_t i = 0; i < a.est_errors[1].x.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.est_errors[1].x[i], alone[i + 40]) << i;
  }
  EXPECT_LT(a.est.x.std, 1.0);
}

TEST(Analyze, TooShortEverywhereIsAnInputErrorNamingTheFirstRow) {
  MeasuredTrack t = Line("robot 1", Range(0, 80), 0.5, 1);
  t.first_line = 7;
  EXPECT_INPUT_ERROR(AnalyzeTracks({t}, AnalyzeOptions{}),
                     "t.csv:7: subject \"robot 1\" has no run of 81 consecutive frames (longest: "
                     "80); expected at least 2 x 40 + 1 for smoothing with sigma = 10 samples");
  AnalyzeOptions s3;
  s3.smoothing.sigma_samples = 3.0;
  EXPECT_EQ(AnalyzeTracks({t}, s3).subjects[0].segments, 1);  // 80 >= 2 x 12 + 1
}

// Heading turning at 0.05 rad/frame through +-pi with noise 0.01 rad: the residuals stay at the
// noise level (unwrapped before smoothing, wrapped after).
TEST(Analyze, OrientationIsUnwrappedAcrossPlusMinusPi) {
  MeasuredTrack t = Line("a", Range(0, 400), 0.5, 3);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (size_t i = 0; i < t.frame.size(); ++i) {
    t.theta.push_back(WrapAngle(2.0 + 0.05 * static_cast<double>(i) + noise(rng)));
  }
  const SubjectAnalysis a = AnalyzeTracks({t}, AnalyzeOptions{}).subjects[0];
  ASSERT_TRUE(a.est.has_theta);
  EXPECT_NEAR(a.est.theta.std, 0.01 * 0.974, 0.002);
}

// Noise only across a 35-degree line: along the travel the errors vanish, across they are the
// noise (times the residual factor).
TEST(Analyze, AlongTravelRotatesIntoTheDirectionOfMotion) {
  const double h = 35.0 * std::numbers::pi / 180.0;
  MeasuredTrack t = Line("a", Range(0, 4000), 0.0, 1, h);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.8);
  for (size_t i = 0; i < t.x.size(); ++i) {
    const double across = noise(rng);
    t.x[i] += -std::sin(h) * across;
    t.y[i] += std::cos(h) * across;
  }
  AnalyzeOptions options;
  options.along_travel = true;
  const SubjectAnalysis a = AnalyzeTracks({t}, options).subjects[0];
  EXPECT_LT(a.est.x.std, 1e-3);  // in the file's axes it would be 0.8 sin(35 deg) 0.974 = 0.45
  EXPECT_NEAR(a.est.y.std, 0.8 * 0.974, 0.03);
}

// The truth adds sample - truth on the same kept samples; a missing truth frame is named.
TEST(Analyze, TruthGivesTheTrueErrorsOfTheSameSamples) {
  MeasuredTrack noisy = Line("a", Range(0, 200), 0.5, 5);
  MeasuredTrack truth = Line("a", Range(0, 200), 0.0, 5);
  truth.run = "other-file.csv";  // matched by subject alone: the only truth track of "a"
  std::vector<MeasuredTrack> truths = {truth};
  const SubjectAnalysis a = AnalyzeTracks({noisy}, AnalyzeOptions{}, &truths).subjects[0];
  ASSERT_TRUE(a.has_truth);
  ASSERT_EQ(a.true_errors[0].x.size(), 120u);
  EXPECT_DOUBLE_EQ(a.true_errors[0].x[0], noisy.x[40] - truth.x[40]);
  EXPECT_DOUBLE_EQ(a.true_errors[0].y[119], noisy.y[159] - truth.y[159]);
  MeasuredTrack& u = truths[0];
  u.frame.erase(u.frame.begin() + 50);
  u.x.erase(u.x.begin() + 50);
  u.y.erase(u.y.begin() + 50);
  EXPECT_INPUT_ERROR(
      AnalyzeTracks({noisy}, AnalyzeOptions{}, &truths),
      "t.csv:2: no truth for subject \"a\" run \"r\" frame 50; expected the truth of "
      "every analysed frame");
}

// Subject b has twice a's noise on frames 0-299 of run r; c shares only frames 200-499: the tests
// pair by (run, frame), and b loses to a on every axis.
TEST(Analyze, WilcoxonPairsSubjectsByRunAndFrame) {
  const MeasuredTrack a = Line("a", Range(0, 300), 0.5, 11);
  const MeasuredTrack b = Line("b", Range(0, 300), 1.0, 12);
  const MeasuredTrack c = Line("c", Range(200, 500), 0.5, 13);
  const AnalyzeReport r = AnalyzeTracks({a, b, c}, AnalyzeOptions{});
  ASSERT_EQ(r.tests.size(), 9u);  // 3 pairs x (x, y, xy)
  const stats::PairedTest& ab = r.tests[0];
  EXPECT_EQ(ab.axis, "x");
  EXPECT_EQ(ab.a, "a");
  EXPECT_EQ(ab.b, "b");
  EXPECT_EQ(ab.result.n, 220u);
  EXPECT_LT(ab.result.p_value, 1e-6);
  EXPECT_LT(ab.result.r_plus, ab.result.r_minus);  // |a| - |b| mostly negative
  EXPECT_EQ(r.tests[1].a + r.tests[1].b, "ac");
  EXPECT_EQ(r.tests[1].result.n, 20u);  // a keeps frames 40-259, c 240-459
}

// Both ways of pairing (subjects with the same frames: by index; others: merged by frame) give
// the test a hand pairing of the per-sample errors gives.
TEST(Analyze, PairedTestsEqualTheTestOfTheHandPairedErrors) {
  const AnalyzeReport r =
      AnalyzeTracks({Line("a", Range(0, 300), 0.5, 11), Line("b", Range(0, 300), 1.0, 12),
                     Line("c", Range(200, 500), 0.5, 13)},
                    AnalyzeOptions{});
  const auto& a = r.subjects[0].est_errors[0];
  std::map<int64_t, double> by_frame;
  for (size_t i = 0; i < a.frame.size(); ++i) by_frame[a.frame[i]] = std::abs(a.x[i]);
  stats::WilcoxonOptions options;
  options.method = stats::WilcoxonMethod::kApprox;
  for (const auto& [k, test] : {std::pair(1, r.tests[0]), std::pair(2, r.tests[1])}) {
    const auto& other = r.subjects[static_cast<size_t>(k)].est_errors[0];
    std::vector<double> va, vb;
    for (size_t i = 0; i < other.frame.size(); ++i) {
      const auto it = by_frame.find(other.frame[i]);
      if (it == by_frame.end()) continue;
      va.push_back(it->second);
      vb.push_back(std::abs(other.x[i]));
    }
    const stats::WilcoxonResult hand = stats::WilcoxonSignedRank(va, vb, options);
    EXPECT_EQ(test.result.n, hand.n);
    EXPECT_EQ(test.result.r_plus, hand.r_plus);
    EXPECT_EQ(test.result.z, hand.z);
    EXPECT_EQ(test.result.p_value, hand.p_value);
  }
}

// The errors CSV handed out in pieces: the rows printf formats, whatever the length of a
// subject's name (one longer than the 256 kB block too); and AnalyzeTracks on moved tracks
// gives what it gives on kept ones.
TEST(Analyze, StreamedErrorsCsvIsTheRowsAndMovedTracksGiveTheSameReport) {
  const std::string long_name(300000, 'n');
  std::vector<MeasuredTrack> tracks = {Line("a", Range(0, 3000), 0.5, 21),
                                       Line(long_name, Range(0, 100), 0.5, 22)};
  const AnalyzeReport kept = AnalyzeTracks(tracks, AnalyzeOptions{});
  std::string expected = "subject,run,frame,est_x_mm,est_y_mm,est_theta_rad\n";
  for (const SubjectAnalysis& s : kept.subjects) {
    const stats::ErrorSegment& e = s.est_errors[0];
    for (size_t i = 0; i < e.frame.size(); ++i) {
      char cells[128];
      std::snprintf(cells, sizeof cells, "%lld,%.4f,%.4f,\n", static_cast<long long>(e.frame[i]),
                    e.x[i], e.y[i]);
      expected.append(s.subject).append(",r,").append(cells);
    }
  }
  std::vector<size_t> pieces;
  std::string text;
  WriteAnalyzeErrorsCsv(kept, [&](std::string_view piece) {
    pieces.push_back(piece.size());
    text.append(piece);
  });
  EXPECT_TRUE(text == expected);
  EXPECT_EQ(AnalyzeErrorsCsv(kept), expected);
  EXPECT_GT(pieces.size(), 2u);
  const AnalyzeReport moved = AnalyzeTracks(std::move(tracks), AnalyzeOptions{});
  EXPECT_TRUE(AnalyzeErrorsCsv(moved) == expected);
  EXPECT_EQ(stats::PairedTestsCsv(moved.tests), stats::PairedTestsCsv(kept.tests));
  EXPECT_EQ(AnalyzeTableCsv(moved), AnalyzeTableCsv(kept));
  EXPECT_TRUE(tracks[0].x.empty());  // NOLINT(bugprone-use-after-move): released as documented
  EXPECT_EQ(tracks[1].subject, long_name);
}

TEST(Analyze, ReadsSubjectsRunsQuotesAndComments) {
  const std::string text =
      "# a comment\n\"frame\", subject ,run,x_mm,y_mm,theta_rad\n"
      "1,a,1,0.5,1.5,0.1\n1,b,1,2,3,0.2\n2,a,1,+0.75,1e1,0.3\n\n2,b,1,4,5,-0.1\r\n";
  const std::vector<MeasuredTrack> t = ParseTrackCsv(text, "in.csv", TrackColumns{});
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].subject, "a");
  EXPECT_EQ(t[0].first_line, 3);
  EXPECT_EQ(t[0].frame, (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(t[0].x, (std::vector<double>{0.5, 0.75}));
  EXPECT_EQ(t[0].y, (std::vector<double>{1.5, 10.0}));
  EXPECT_EQ(t[1].theta, (std::vector<double>{0.2, -0.1}));
  // Without subject, run and theta columns: one subject "track", the run named by the file.
  const std::vector<MeasuredTrack> bare = ParseTrackCsv("frame,x_mm,y_mm\n0,1,2\n", "b.csv", {});
  EXPECT_EQ(bare[0].subject, "track");
  EXPECT_EQ(bare[0].run, "b.csv");
  EXPECT_TRUE(bare[0].theta.empty());
}

// ReadTrackCsv reads in 1 MB blocks: a 3 MB file (lines across block ends, no final newline)
// reads as ParseTrackCsv parses the same text.
TEST(Analyze, ReadingInBlocksGivesWhatParsingTheWholeTextGives) {
  std::string text = "frame,subject,x_mm,y_mm,theta_rad\n# comment\n";
  for (int f = 0; f < 60000; ++f) {
    text += std::to_string(f) + ",s" + std::to_string(f % 3) + "," + std::to_string(f * 0.25) +
            ",-12.0625," + std::to_string(f % 7) + "\n";
  }
  text.pop_back();
  const std::string path = ::testing::TempDir() + "analyze_blocks.csv";
  { std::ofstream(path, std::ios::binary) << text; }
  const std::vector<MeasuredTrack> read = ReadTrackCsv(path, TrackColumns{});
  const std::vector<MeasuredTrack> parsed = ParseTrackCsv(text, path, TrackColumns{});
  ASSERT_EQ(read.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(read[k].frame, parsed[k].frame);
    EXPECT_EQ(read[k].x, parsed[k].x);
    EXPECT_EQ(read[k].theta, parsed[k].theta);
  }
  EXPECT_EQ(read[2].frame.back(), 59999);
  std::filesystem::remove(path);
}

TEST(Analyze, BadTrackFilesAreInputErrorsWithFileAndLine) {
  const TrackColumns c;
  const std::string h = "frame,subject,x_mm,y_mm\n";
  EXPECT_INPUT_ERROR(ParseTrackCsv("frame,subject,x,y_mm\n1,a,2,3\n", "f.csv", c),
                     "f.csv:1: no column \"x_mm\" in the header; expected the x column (or name it "
                     "with --x-column)");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "1,a,2,3\n2,a,nan,3\n", "f.csv", c),
                     "f.csv:3: column 3 ('x_mm'): 'nan' is not a finite number; expected a "
                     "finite number");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "1,a,2,\n", "f.csv", c),
                     "f.csv:2: column 4 ('y_mm'): '' is not a number; expected a finite number");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "1.5,a,2,3\n", "f.csv", c),
                     "f.csv:2: column 1 ('frame'): '1.5' is not an integer; expected an integer "
                     "frame number");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "5,a,2,3\n6,b,2,3\n4,a,2,3\n", "f.csv", c),
                     "f.csv:4: frame 4 of subject \"a\" run \"f.csv\" is not after 5 (line 2); "
                     "expected increasing frame numbers within a subject and run");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "5,a,2,3\n5,a,2,3\n", "f.csv", c),
                     "f.csv:3: frame 5 of subject \"a\" run \"f.csv\" is not after 5 (line 2); "
                     "expected increasing frame numbers within a subject and run");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "5,a,2\n", "f.csv", c),
                     "f.csv:2: row has 3 cells; expected at least 4 as the header names them");
  EXPECT_INPUT_ERROR(ParseTrackCsv("# only\n\n", "f.csv", c),
                     "f.csv: no header; expected a header row naming the columns, then one sample "
                     "a row");
  EXPECT_INPUT_ERROR(ParseTrackCsv(h, "f.csv", c),
                     "f.csv:1: no samples after the header; expected one sample a row");
  TrackColumns theta;
  theta.require_theta = true;
  EXPECT_INPUT_ERROR(ParseTrackCsv(h + "1,a,2,3\n", "f.csv", theta),
                     "f.csv:1: no column \"theta_rad\" in the header; expected the theta column "
                     "(or name it with --theta-column)");
  TrackColumns same;
  same.y = "x_mm";
  EXPECT_INPUT_ERROR(ParseTrackCsv(h, "f.csv", same),
                     "--y-column and --x-column are both \"x_mm\"; expected different columns");
}

TEST(Analyze, ASubjectAndRunInTwoFilesIsAnInputError) {
  MeasuredTrack a = Line("a", Range(0, 100), 0.5, 1);
  MeasuredTrack b = Line("a", Range(100, 200), 0.5, 2);
  b.file = "u.csv";
  b.first_line = 4;
  EXPECT_INPUT_ERROR(AnalyzeTracks({a, b}, AnalyzeOptions{}),
                     "u.csv:4: subject \"a\" run \"r\" is also in t.csv; expected each subject "
                     "and run in one file");
}

TEST(Analyze, OptionsAreChecked) {
  AnalyzeOptions o;
  o.smoothing.sigma_samples = 0.0;
  EXPECT_INPUT_ERROR(Validate(o), "sigma_samples is 0; expected a finite number > 0 (samples)");
  o = AnalyzeOptions{};
  o.lag = 0;
  EXPECT_INPUT_ERROR(Validate(o), "lag is 0; expected an integer in [1, 1000000]");
}

}  // namespace
}  // namespace patlab::analysis

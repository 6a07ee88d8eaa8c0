// End-to-end tests of `patlab simulate` with correspondence = "detect": the real binary, real
// files (shipped patterns and SSL codebook).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kPatlab;
using testing::RunCommand;

std::string Settings() {
  return "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"white\", \"orange\"]\n"
         "patterns_dir = \"" PATLAB_SOURCE_DIR
         "/patterns\"\n"
         "[detector]\npatch_sigma_mm = 1.0\n"
         "[[pattern]]\npattern = \"ssl-standard\"\n"
         "codebook = \"" PATLAB_SOURCE_DIR
         "/patterns/ssl-standard.codebook.toml\"\n"
         "key_colours = [\"blue\", \"yellow\"]\n"
         "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"pink\", \"green\", \"cyan\"]\n"
         "key_colours = [\"blue\", \"yellow\"]\n";
}

// Lines: 1 name, 2 correspondence, 3 patterns, 4 seed, 5-6 [sigma], 7 [detect], 8 settings,
// 9 frames, 10 false_blob_rate_per_m2, 11 detector_sigma, 12 `extra`.
std::string TinyDetectExperiment(const std::string& extra = "", const std::string& frames = "200",
                                 const std::string& detector_sigma = "\"matched\"") {
  return "name = \"tiny\"\ncorrespondence = \"detect\"\npatterns = [\"ssl-standard\", "
         "\"triangle\"]\nseed = 11\n[sigma]\nvalues = [0, 1, 5]\n"
         "[detect]\nsettings = \"det.toml\"\nframes = " +
         frames + "\nfalse_blob_rate_per_m2 = [0, 2]\ndetector_sigma = " + detector_sigma + "\n" +
         extra;
}

TEST(SimulateDetectCli, WritesTidyCsvAndManifestIdenticalForAnyThreadCount) {
  testing::TempDir dir;
  dir.Write("det.toml", Settings());
  const std::string experiment = dir.Write("tiny.toml", TinyDetectExperiment());
  const auto one =
      RunCommand(kPatlab + " simulate " + experiment + " --threads 1 -q --out " + dir.Path("one"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.err, "");
  const auto two =
      RunCommand(kPatlab + " simulate " + experiment + " --threads 2 --out " + dir.Path("two"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_NE(two.err.find("patlab simulate: 2400 frames in "), std::string::npos) << two.err;
  const std::string csv = testing::ReadFile(dir.Path("one/tiny.csv"));
  EXPECT_EQ(csv, testing::ReadFile(dir.Path("two/tiny.csv")));
  // Header + 2 patterns x 2 false-blob rates x 3 sigmas.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 2 * 3);
  EXPECT_EQ(csv.rfind("pattern,sigma_mm,false_blob_rate_per_m2,point,frames,robots,noise,"
                      "detector_sigma_mm,tolerance_mm2,correct,wrong_id,unknown_id,ambiguous,"
                      "missed,false_positives,detection_rate,detection_rate_lo,"
                      "detection_rate_hi,wrong_id_rate,",
                      0),
            0u)
      << csv;
  // Exact blobs without false ones: every robot detected with its ID, no false positives.
  EXPECT_NE(csv.find("\nssl-standard,0,0,0,200,2000,isotropic,1,29.8775039"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",2000,0,0,0,0,0,1,0.99808"), std::string::npos) << csv;

  const auto manifest = nlohmann::json::parse(testing::ReadFile(dir.Path("one/tiny.json")));
  EXPECT_EQ(manifest["correspondence"], "detect");
  EXPECT_EQ(manifest["seed"], 11);
  EXPECT_EQ(manifest["frames_per_point"], 200);
  EXPECT_EQ(manifest["total_frames"], 2400);
  EXPECT_FALSE(manifest.contains("threads"));
  EXPECT_FALSE(manifest.contains("frames_per_second"));
  EXPECT_EQ(manifest["false_blob_rates_per_m2"], nlohmann::json::array({0, 2}));
  EXPECT_EQ(manifest["detect"]["detector_sigma"], "matched");
  EXPECT_EQ(manifest["detector"]["estimator"], "fast");
  EXPECT_EQ(manifest["patterns"].size(), 2u);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.Path("one"))) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 2);
}

TEST(SimulateDetectCli, TrialsSetFramesAndSigmasOverride) {
  testing::TempDir dir;
  dir.Write("det.toml", Settings());
  const std::string experiment = dir.Write("tiny.toml", TinyDetectExperiment());
  const auto r = RunCommand(kPatlab + " simulate " + experiment +
                            " -q --trials 7 --sigmas 2 --out " + dir.Path("o"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = testing::ReadFile(dir.Path("o/tiny.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 2 * 1);
  EXPECT_NE(csv.find("\ntriangle,2,2,3,7,70,isotropic,2,"), std::string::npos) << csv;
}

TEST(SimulateDetectCli, BadDetectTablesExitTwoWithTheirMessages) {
  testing::TempDir dir;
  dir.Write("det.toml", Settings());
  const std::string out = " -q --out " + dir.Path("out");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {TinyDetectExperiment("", "0"),
       ":9: frames in [detect] is 0; expected an integer in [1, 100000000]"},
      {TinyDetectExperiment("colour_error_probability = 2\n"),
       ":12: colour_error_probability in [detect] is 2; expected a probability in [0, 1]"},
      {TinyDetectExperiment("robots_per_team = 17\n"),
       ":12: robots_per_team in [detect] is 17; expected at most 16 (the IDs of ssl-standard)"},
      {TinyDetectExperiment("", "200", "\"auto\""),
       ":11: detector_sigma in [detect] is \"auto\"; expected \"settings\" or \"matched\""},
  };
  for (const auto& [text, message] : cases) {
    const std::string experiment = dir.Write("bad.toml", text);
    const auto r = RunCommand(kPatlab + " simulate " + experiment + out);
    EXPECT_EQ(r.exit_code, 2) << text;
    EXPECT_EQ(r.err, "patlab simulate: " + experiment + message + "\n") << text;
  }
  const std::string experiment = dir.Write("tiny.toml", TinyDetectExperiment());
  const auto r = RunCommand(kPatlab + " simulate " + experiment + " --trials -1" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "patlab simulate: --trials is -1; expected an integer in [1, 100000000] (frames "
            "per point in detect mode)\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
}

TEST(SimulateDetectCli, ReplayPrintsOneFrame) {
  testing::TempDir dir;
  dir.Write("det.toml", Settings());
  const std::string experiment = dir.Write("tiny.toml", TinyDetectExperiment());
  const auto r = RunCommand(kPatlab + " simulate " + experiment + " --replay 10,3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("point 10 (pattern triangle, sigma 1 mm, false blobs 2 /m^2), frame 3, "
                       "seed 11\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("score      robots 10 correct "), std::string::npos) << r.out;
  const auto bad = RunCommand(kPatlab + " simulate " + experiment + " --replay 12,0");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(
      bad.err,
      "patlab simulate: --replay 12,0 is out of range; expected POINT < 12 and FRAME < 200\n");
}

}  // namespace
}  // namespace patlab

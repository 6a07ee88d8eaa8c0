// Experiment files with correspondence = "detect": the [detect] table, its defaults and every
// bad-file message, word for word.
#include <gtest/gtest.h>

#include "../experiment_fixture.h"
#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/experiment.h"

namespace patlab::formats {
namespace {

// <dir>/patterns/ holds copies of shipped patterns, <dir>/experiments/ the detector settings
// (det.toml) and the experiment (e.toml), as in the repository.
class DetectExperimentTest : public sim::testing_support::ExperimentFixture {
 protected:
  void SetUp() override {
    CopyPatterns({"simple", "butterfly", "triangle"});
    dir_.Write("experiments/det.toml",
               "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"white\", "
               "\"orange\"]\n"
               "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n"
               "[[pattern]]\npattern = \"triangle\"\n"
               "id_colours = [\"pink\", \"green\", \"cyan\", \"white\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n");
    dir_.Write("experiments/no-orange.toml",
               "palette = [\"blue\", \"yellow\", \"pink\", \"green\"]\n"
               "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n");
  }
};

// Lines 1-3 head, 4-5 [sigma], [detect] from line 6.
const std::string kDetectHead =
    "name = \"x\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\", \"triangle\"]\n";
const std::string kDetectSigma = "[sigma]\nvalues = [0, 1]\n";
const std::string kDetect = "[detect]\nsettings = \"det.toml\"\n";

TEST_F(DetectExperimentTest, DefaultsAndPatternsFromTheSettings) {
  const sim::Experiment e = LoadExperimentFile(Write(kDetectHead + kDetectSigma + kDetect));
  EXPECT_EQ(e.correspondence, sim::Correspondence::kDetect);
  ASSERT_EQ(e.patterns.size(), 2u);
  EXPECT_EQ(e.patterns[0].name, "butterfly");
  EXPECT_EQ(e.patterns[1].name, "triangle");
  EXPECT_EQ(e.detect.detector_pattern, (std::vector<int>{0, 1}));
  EXPECT_EQ(e.pattern_files[0], dir_.Path("experiments/det.toml"));
  EXPECT_EQ(e.detect.settings_file, dir_.Path("experiments/det.toml"));
  EXPECT_EQ(e.detect.frames, 1000);
  EXPECT_EQ(e.detect.scene.robots_per_team, 5);
  EXPECT_EQ(e.detect.false_blob_rates_per_m2, (std::vector<double>{0.0}));
  EXPECT_EQ(e.detect.scene.missing_patch_probability, 0.0);
  EXPECT_EQ(e.detect.scene.colour_error_probability, 0.0);
  EXPECT_TRUE(e.detect.scene.ball);
  EXPECT_EQ(e.detect.match_radius_mm, 45.0);
  EXPECT_FALSE(e.detect.matched_sigma);
  // The scene stands on the experiment's field (default: the paper's F180 field).
  EXPECT_EQ(e.detect.scene.field_length_mm, 2800.0);
  EXPECT_EQ(e.detect.scene.field_width_mm, 2300.0);
}

TEST_F(DetectExperimentTest, EveryKeyIsRead) {
  const sim::Experiment e = LoadExperimentFile(
      Write(kDetectHead + kDetectSigma + "[field]\nlength_mm = 4000\nwidth_mm = 3000\n" + kDetect +
            "frames = 77\nrobots_per_team = 3\nfalse_blob_rate_per_m2 = [0, 0.5, 2]\n"
            "false_blob_radius_min_mm = 5\nfalse_blob_radius_max_mm = 9\n"
            "missing_patch_probability = 0.1\ncolour_error_probability = 0.02\nball = false\n"
            "ball_colour = \"white\"\nrobot_radius_mm = 80\nmin_separation_mm = 200\n"
            "match_radius_mm = 30\ndetector_sigma = \"matched\"\n"));
  const sim::DetectSettings& d = e.detect;
  EXPECT_EQ(d.frames, 77);
  EXPECT_EQ(d.scene.robots_per_team, 3);
  EXPECT_EQ(d.false_blob_rates_per_m2, (std::vector<double>{0.0, 0.5, 2.0}));
  EXPECT_EQ(d.scene.false_blob_radius_min_mm, 5.0);
  EXPECT_EQ(d.scene.false_blob_radius_max_mm, 9.0);
  EXPECT_EQ(d.scene.missing_patch_probability, 0.1);
  EXPECT_EQ(d.scene.colour_error_probability, 0.02);
  EXPECT_FALSE(d.scene.ball);
  EXPECT_EQ(d.scene.ball_colour, "white");
  EXPECT_EQ(d.scene.robot_radius_mm, 80.0);
  EXPECT_EQ(d.scene.min_separation_mm, 200.0);
  EXPECT_EQ(d.scene.field_length_mm, 4000.0);
  EXPECT_EQ(d.match_radius_mm, 30.0);
  EXPECT_TRUE(d.matched_sigma);
  // One number is a one-value axis.
  const sim::Experiment one = LoadExperimentFile(
      Write(kDetectHead + kDetectSigma + kDetect + "false_blob_rate_per_m2 = 1.5\n"));
  EXPECT_EQ(one.detect.false_blob_rates_per_m2, (std::vector<double>{1.5}));
}

TEST_F(DetectExperimentTest, ShippedIdConfusionLoads) {
  const sim::Experiment e =
      LoadExperimentFile(std::string(PATLAB_SOURCE_DIR) + "/experiments/id_confusion.toml");
  EXPECT_EQ(e.correspondence, sim::Correspondence::kDetect);
  ASSERT_EQ(e.patterns.size(), 3u);
  EXPECT_EQ(e.patterns[0].name, "butterfly");
  EXPECT_EQ(e.patterns[1].name, "ssl-standard");
  EXPECT_EQ(e.patterns[2].name, "triangle");
  EXPECT_TRUE(e.detect.matched_sigma);
  EXPECT_GE(e.sigmas_mm.size(), 10u);
  EXPECT_GE(e.detect.false_blob_rates_per_m2.size(), 2u);
}

TEST_F(DetectExperimentTest, BadFilesGiveTheirMessages) {
  const std::string keys =
      "settings, frames, robots_per_team, false_blob_rate_per_m2, false_blob_radius_min_mm, "
      "false_blob_radius_max_mm, missing_patch_probability, colour_error_probability, ball, "
      "ball_colour, robot_radius_mm, min_separation_mm, match_radius_mm, detector_sigma";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {kDetectHead + kDetectSigma,
       "e.toml:1: missing [detect] with correspondence = \"detect\"; expected a table with at "
       "least settings = \"<detector settings file>\""},
      {kDetectHead + kDetectSigma + "[detect]\nframes = 10\n",
       "e.toml:6: missing settings in [detect]; expected a detector settings file (relative to "
       "the experiment)"},
      {kDetectHead + kDetectSigma + "[detect]\nsettings = \"nope.toml\"\n",
       "e.toml:7: settings in [detect] is \"nope.toml\", but " +
           dir_.Path("experiments/nope.toml") +
           " is not a file; expected a detector settings file (relative to the experiment)"},
      {kDetectHead + "trials = 100\n" + kDetectSigma + kDetect,
       "e.toml:4: trials is not used with correspondence = \"detect\"; expected frames in "
       "[detect]"},
      {kDetectHead + "estimators = [\"ml\"]\n" + kDetectSigma + kDetect,
       "e.toml:4: estimators is not used with correspondence = \"detect\"; expected estimator in "
       "the detector settings' [detector] table"},
      {kDetectHead + "frames = 100\n" + kDetectSigma + kDetect,
       "e.toml:4: unknown key 'frames'; expected one of: name, description, patterns, seed, "
       "correspondence, sigma, field, noise, noise_file, detect"},
      {kDetectHead + kDetectSigma + kDetect + "frame = 10\n",
       "e.toml:8: unknown key 'frame' in [detect]; expected one of: " + keys},
      {kDetectHead + kDetectSigma + kDetect + "frames = 0\n",
       "e.toml:8: frames in [detect] is 0; expected an integer in [1, 100000000]"},
      {kDetectHead + kDetectSigma + kDetect + "robots_per_team = 0\n",
       "e.toml:8: robots_per_team in [detect] is 0; expected an integer in [1, 1000]"},
      {kDetectHead + kDetectSigma + kDetect + "robots_per_team = 17\n",
       "e.toml:8: robots_per_team in [detect] is 17; expected at most 16 (the IDs of butterfly)"},
      {kDetectHead + kDetectSigma + "[field]\nlength_mm = 500\nwidth_mm = 500\n" + kDetect,
       "e.toml:9: robots_per_team in [detect] is 5 (butterfly): 10 robots 180 mm apart and the "
       "ball exclude 895% of the area their centres are drawn from; expected at most 80% (a "
       "larger field, fewer robots or a smaller min_separation_mm)"},
      {kDetectHead + kDetectSigma + "[field]\nwidth_mm = 0\n" + kDetect,
       "e.toml:7: width_mm in [field] is 0; expected a finite number > 0 (mm) with "
       "correspondence = \"detect\""},
      {kDetectHead + kDetectSigma + kDetect + "false_blob_rate_per_m2 = [2, 1]\n",
       "e.toml:8: false_blob_rate_per_m2 in [detect] is not increasing at 1; expected strictly "
       "increasing values"},
      {kDetectHead + kDetectSigma + kDetect + "false_blob_rate_per_m2 = -1\n",
       "e.toml:8: false_blob_rate_per_m2 in [detect] is -1; expected a number in [0, 1000]"},
      {kDetectHead + kDetectSigma + kDetect + "false_blob_rate_per_m2 = [1, \"many\"]\n",
       "e.toml:8: false_blob_rate_per_m2 in [detect] is a string; expected a number or an array "
       "of numbers"},
      {kDetectHead + kDetectSigma + kDetect + "false_blob_rate_per_m2 = []\n",
       "e.toml:8: false_blob_rate_per_m2 in [detect] is empty; expected a number or an array of "
       "numbers"},
      {kDetectHead + kDetectSigma + kDetect + "missing_patch_probability = 1.5\n",
       "e.toml:8: missing_patch_probability in [detect] is 1.5; expected a probability in [0, 1]"},
      {kDetectHead + kDetectSigma + kDetect + "colour_error_probability = -0.1\n",
       "e.toml:8: colour_error_probability in [detect] is -0.1; expected a probability in [0, 1]"},
      {kDetectHead + kDetectSigma + kDetect + "false_blob_radius_max_mm = 5\n",
       "e.toml:8: false_blob_radius_max_mm in [detect] is 5; expected a finite number >= "
       "false_blob_radius_min_mm"},
      {kDetectHead + kDetectSigma + kDetect + "match_radius_mm = 0\n",
       "e.toml:8: match_radius_mm in [detect] is 0; expected a finite number > 0 (mm)"},
      {kDetectHead + kDetectSigma + kDetect + "detector_sigma = \"auto\"\n",
       "e.toml:8: detector_sigma in [detect] is \"auto\"; expected \"settings\" or \"matched\""},
      {kDetectHead + kDetectSigma + "[detect]\nsettings = \"no-orange.toml\"\n",
       "e.toml:6: ball_colour in [detect] is \"orange\"; expected a colour of the detector "
       "palette (blue, yellow, pink, green) or ball = false"},
      {"name = \"x\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\", \"simple\"]\n" +
           kDetectSigma + kDetect,
       "e.toml:3: pattern 'simple' is not in the detector settings " +
           dir_.Path("experiments/det.toml") + "; expected one of: butterfly, triangle"},
      {"name = \"x\"\ncorrespondence = \"detect\"\npatterns = [\"triangle\", \"triangle\"]\n" +
           kDetectSigma + kDetect,
       "e.toml:3: pattern 'triangle' is listed twice; expected each pattern once"},
      // Known mode does not know [detect].
      {"name = \"x\"\npatterns = [\"simple\"]\n" + kDetectSigma + kDetect,
       "e.toml:5: unknown key 'detect'; expected one of: name, description, patterns, "
       "patterns_dir, estimators, trials, seed, correspondence, sigma, field, noise, noise_file, "
       "ml"},
      {"name = \"x\"\ncorrespondence = \"guess\"\npatterns = [\"simple\"]\n" + kDetectSigma,
       "e.toml:2: correspondence is \"guess\"; expected \"known\" or \"detect\""},
  };
  for (const auto& [text, message] : cases) ExpectLoadError(text, message);
}

TEST_F(DetectExperimentTest, BadDetectorSettingsReportTheSettingsFile) {
  dir_.Write("experiments/broken.toml", "palette = [\"blue\"]\n[detector]\npatch_sigma_mm = -1\n");
  ExpectLoadError(kDetectHead + kDetectSigma + "[detect]\nsettings = \"broken.toml\"\n",
                  "broken.toml:3: patch_sigma_mm is -1; expected a finite number > 0 (mm)");
}

TEST_F(DetectExperimentTest, TrialsOverrideSetsFrames) {
  sim::Experiment e = LoadExperimentFile(Write(kDetectHead + kDetectSigma + kDetect));
  sim::Overrides o;
  o.trials = 1;
  sim::ApplyOverrides(o, &e);
  EXPECT_EQ(e.detect.frames, 1);
  EXPECT_EQ(e.trials, 100000);  // the known-mode field is untouched
  o.trials = -3;
  EXPECT_INPUT_ERROR(sim::ApplyOverrides(o, &e),
                     "--trials is -3; expected an integer in [1, 100000000] (frames per point in "
                     "detect mode)");
}

}  // namespace
}  // namespace patlab::formats

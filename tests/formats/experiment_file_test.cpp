#include "patlab/formats/experiment_file.h"

#include <gtest/gtest.h>

#include "../experiment_fixture.h"
#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/sim/experiment.h"

namespace patlab::formats {
namespace {

// Experiment files live in <dir>/experiments/, patterns in <dir>/patterns/ (a copy of two
// shipped ones), as in the repository.
class ExperimentFileTest : public sim::testing_support::ExperimentFixture {
 protected:
  void SetUp() override { CopyPatterns({"simple", "butterfly"}); }
};

const std::string kHead = "name = \"x\"\npatterns = [\"simple\", \"butterfly\"]\n";
const std::string kSigma = "[sigma]\nfrom = 0\nto = 4\nsteps = 17\n";

TEST_F(ExperimentFileTest, ShippedFig5HasThePapersSetUp) {
  const sim::Experiment e =
      LoadExperimentFile(std::string(PATLAB_SOURCE_DIR) + "/experiments/fig5.toml");
  ASSERT_EQ(e.patterns.size(), 5u);
  EXPECT_EQ(e.patterns[4].name, "ssl-standard");
  EXPECT_EQ(e.trials, 100000);
  ASSERT_GE(e.sigmas_mm.size(), 15u);
  EXPECT_EQ(e.sigmas_mm.front(), 0.0);
  EXPECT_EQ(e.sigmas_mm.back(), 4.0);
  EXPECT_EQ(e.estimators, (std::vector<estimate::Estimator>{estimate::Estimator::kFast,
                                                            estimate::Estimator::kMl}));
  EXPECT_TRUE(e.noise.IsIsotropicGaussian());
  EXPECT_EQ(e.field_length_mm, 2800.0);
  EXPECT_EQ(e.field_width_mm, 2300.0);
}

TEST_F(ExperimentFileTest, DefaultsAndGridForms) {
  sim::Experiment e = LoadExperimentFile(Write(kHead + kSigma));
  EXPECT_EQ(e.trials, 100000);
  EXPECT_EQ(e.sigmas_mm.size(), 17u);
  EXPECT_DOUBLE_EQ(e.sigmas_mm[1], 0.25);
  e = LoadExperimentFile(Write(kHead + "[sigma]\nvalues = [0.5, 1, 2]\n"));
  EXPECT_EQ(e.sigmas_mm, (std::vector<double>{0.5, 1.0, 2.0}));
}

TEST_F(ExperimentFileTest, NoiseFileIsReadRelativeToTheExperiment) {
  dir_.Write("experiments/noise/jitter.toml", "common_sigma_ratio = 0.5\nsigma_y_ratio = 2\n");
  const sim::Experiment e =
      LoadExperimentFile(Write(kHead + "noise_file = \"noise/jitter.toml\"\n" + kSigma));
  EXPECT_EQ(e.noise.common_sigma_ratio, 0.5);
  EXPECT_EQ(e.noise.sigma_y_ratio, 2.0);
}

TEST_F(ExperimentFileTest, BadFilesGiveTheirMessages) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {kHead + "trials = 1\n" + kSigma,
       "e.toml:3: trials is 1; expected an integer in [2, 1000000000]"},
      {kHead + "estimators = [\"fast\", \"newton\"]\n" + kSigma,
       "e.toml:3: unknown estimator \"newton\"; expected \"fast\", \"ml\", \"lsq\", \"key\" or "
       "\"robust\""},
      {kHead + "estimators = [\"ml\", \"ml\"]\n" + kSigma,
       "e.toml:3: estimator \"ml\" is listed twice; expected each once"},
      {"name = \"x\"\npatterns = [\"hexagon\"]\n" + kSigma,
       "e.toml:2: pattern 'hexagon' not found; expected a pattern file path or a name in " +
           dir_.Path("patterns") + "/"},
      {kHead + "seeds = 3\n" + kSigma,
       "e.toml:3: unknown key 'seeds'; expected one of: name, description, patterns, patterns_dir, "
       "estimators, trials, seed, correspondence, sigma, field, noise, noise_file, ml"},
      {kHead, "e.toml:1: missing [sigma]; expected a table with values = [...] or from, to, steps"},
      {kHead + "[sigma]\nvalues = [1, 0.5]\n",
       "e.toml:4: values in [sigma] has 0.5; expected strictly increasing finite numbers >= 0 "
       "(mm)"},
      {kHead + "[sigma]\nvalues = [-1]\n",
       "e.toml:4: values in [sigma] has -1; expected strictly increasing finite numbers >= 0 "
       "(mm)"},
      {kHead + "[sigma]\nfrom = 0\nto = 4\nsteps = 1\n",
       "e.toml:6: steps in [sigma] is 1; expected an integer in [2, 10000]"},
      {kHead + "[sigma]\nfrom = 0\nto = 4\nsteps = 3\nvalues = [1]\n",
       "e.toml:7: [sigma] has both values and from/to/steps; expected one of the two forms"},
      {kHead + kSigma + "[noise]\noutlier_probability = 1.5\n",
       "e.toml:8: outlier_probability in [noise] is 1.5; expected a probability in [0, 1)"},
      {kHead + kSigma + "[noise]\nsigma_y_ratio = 0\n",
       "e.toml:8: sigma_y_ratio in [noise] is 0; expected a finite number > 0"},
      {kHead + kSigma + "[noise]\nsigma = 3\n",
       "e.toml:8: unknown key 'sigma' in [noise]; expected one of: sigma_y_ratio, "
       "common_sigma_ratio, outlier_probability, outlier_sigma_ratio, rotation_jitter_rad, "
       "scale_jitter_ppm, correlation_length_mm, key_shift_x_mm, id_shift_x_mm"},
      {kHead + kSigma + "[noise]\nrotation_jitter_rad = 0.2\n",
       "e.toml:8: rotation_jitter_rad in [noise] is 0.2; expected a number in [0, 0.1] (rad)"},
      {kHead + kSigma + "[noise]\ncorrelation_length_mm = -1\n",
       "e.toml:8: correlation_length_mm in [noise] is -1; expected a finite number >= 0 (mm)"},
      {kHead + kSigma + "[noise]\nscale_jitter_ppm = 2e5\n",
       "e.toml:8: scale_jitter_ppm in [noise] is 200000; expected a number in [0, 100000] (ppm)"},
      {kHead + kSigma + "[noise]\nid_shift_x_mm = nan\n",
       "e.toml:8: id_shift_x_mm in [noise] is nan; expected a finite number"},
      {kHead + kSigma + "[ml]\nmax_iterations = 0\n",
       "e.toml:8: max_iterations in [ml] is 0; expected an integer in [1, 1000]"},
      {kHead + "correspondence = \"guess\"\n" + kSigma,
       "e.toml:3: correspondence is \"guess\"; expected \"known\" or \"detect\""},
      {kHead + "trials = \"many\"\n" + kSigma, "e.toml:3: trials is a string; expected an integer"},
      {"name = \"x\"\npatterns = [\"simple\", \"simple\"]\n" + kSigma,
       "e.toml:2: pattern 'simple' is listed twice; expected each pattern once"},
  };
  for (const auto& [text, message] : cases) ExpectLoadError(text, message);
}

TEST_F(ExperimentFileTest, BadPatternFileReportsThePatternFileAndLine) {
  dir_.Write("patterns/broken.toml",
             "name = \"b\"\n[[patch]]\nrole = \"id\"\nx = 0\ny = 0\nradius = 1\n"
             "[[patch]]\nrole = \"id\"\nx = 5\ny = 0\nradius = 1\n");
  ExpectLoadError("name = \"x\"\npatterns = [\"broken\"]\n" + kSigma,
                  dir_.Path("patterns/broken.toml") +
                      ":2: no key patch; expected exactly one patch with role = \"key\"");
}

}  // namespace
}  // namespace patlab::formats

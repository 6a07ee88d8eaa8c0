// EvaluatePattern as a library call: the four parts of the report and its option checks.
#include "patlab/design/evaluate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"

namespace patlab::design {
namespace {

EvaluateOptions SmallEvaluation() {
  EvaluateOptions o;
  o.trials = 2000;
  o.frames = 10;
  o.sigmas_mm = {1.0, 2.0};
  o.threads = 1;
  return o;
}

TEST(EvaluatePattern, FillsEveryPart) {
  const Pattern pattern = testing::ShippedPattern("butterfly");
  const EvaluationReport r = EvaluatePattern(pattern, "butterfly.toml", SmallEvaluation());
  EXPECT_EQ(r.geometry.size(), estimate::kAllEstimators.size());
  ASSERT_EQ(r.monte_carlo.points.size(), 1u);
  EXPECT_EQ(r.monte_carlo.points[0].trials, 2000);
  EXPECT_EQ(r.ids.counts.size(), 3u);
  EXPECT_TRUE(r.misidentification.run);
  EXPECT_EQ(r.misidentification.codebook, "generated");
  EXPECT_EQ(r.misidentification.result.points.size(), 2u);
  const std::string text = EvaluationText(r);
  EXPECT_EQ(text.rfind("pattern butterfly (butterfly.toml): ", 0), 0u) << text;
  EXPECT_NE(text.find("4. Misidentification in whole frames"), std::string::npos) << text;
  EXPECT_NE(EvaluationJson(SmallEvaluation(), {r}).find("\"tool\": \"patlab evaluate\""),
            std::string::npos);
}

// Part 4 derives max_neighbours from the pattern: the detector default (8) would refuse every
// pattern of more than 9 patches ("max_neighbours is 8; expected at least 10").
TEST(EvaluatePattern, AcceptsPatternsOfMoreThanNinePatches) {
  std::string text = "name = \"eleven\"\n[[patch]]\nrole = \"key\"\nx = 0\ny = 0\nradius = 10\n";
  for (int k = 0; k < 10; ++k) {
    const double angle = 0.6283185307179586 * k, r = 60.0 + 5.0 * k;
    text += "[[patch]]\nrole = \"id\"\nx = " + std::to_string(r * std::cos(angle)) +
            "\ny = " + std::to_string(r * std::sin(angle)) + "\nradius = 10\n";
  }
  const Pattern pattern = formats::ParsePattern(text, "eleven.toml");
  ASSERT_EQ(pattern.size(), 11);
  EvaluateOptions o = SmallEvaluation();
  o.sigmas_mm = {1.0};
  const EvaluationReport r = EvaluatePattern(pattern, "eleven.toml", o);
  EXPECT_TRUE(r.misidentification.run);
  EXPECT_EQ(r.misidentification.result.points.size(), 1u);
}

TEST(EvaluatePattern, ReportDoesNotDependOnThreads) {
  const Pattern pattern = testing::ShippedPattern("triangle");
  EvaluateOptions two = SmallEvaluation();
  two.threads = 2;
  EXPECT_EQ(EvaluationText(EvaluatePattern(pattern, "t.toml", SmallEvaluation())),
            EvaluationText(EvaluatePattern(pattern, "t.toml", two)));
}

TEST(EvaluateOptions, CheckNamesTheFlags) {
  EvaluateOptions o = SmallEvaluation();
  o.id_colours = 9;
  EXPECT_INPUT_ERROR(Validate(o), "--id-colors is 9; expected an integer in [1, 8]");
  o = SmallEvaluation();
  o.sigmas_mm = {2.0, 1.0};
  EXPECT_INPUT_ERROR(Validate(o),
                     "--sigmas has 1; expected strictly increasing finite numbers >= 0 (mm)");
  o = SmallEvaluation();
  o.trials = 1;
  o.frames = 0;
  const std::vector<OptionsProblem> problems = Check(o);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].field, "--trials");
  EXPECT_EQ(problems[1].message, "--frames is 0; expected an integer in [1, 100000000]");
}

TEST(NoiseModel, CheckReportsEveryBrokenField) {
  sim::NoiseModel noise;
  noise.sigma_y_ratio = 0.0;
  noise.outlier_probability = 1.0;
  const std::vector<OptionsProblem> problems = Check(noise);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].message, "sigma_y_ratio is 0; expected a finite number > 0");
  EXPECT_EQ(problems[1].message, "outlier_probability is 1; expected a probability in [0, 1)");
  EXPECT_TRUE(Check(sim::NoiseModel{}).empty());
}

TEST(RunOptions, ThreadsMustNotBeNegative) {
  sim::RunOptions options;
  options.threads = -1;
  EXPECT_INPUT_ERROR(Validate(options),
                     "threads is -1; expected an integer in [0, 4096] (0 = all cores)");
}

}  // namespace
}  // namespace patlab::design

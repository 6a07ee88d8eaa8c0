// patlab evaluate, end to end: runs the built binary on the shipped patterns with small runs.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::CommandResult;
using testing::RunCommand;

CommandResult Evaluate(const std::string& args) {
  return RunCommand("cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " evaluate " + args);
}

// Small runs: the whole file stays well under 5 s.
constexpr const char* kSmallEvaluation = " --trials 4000 --frames 20 --sigmas 1,2";

const nlohmann::json& Estimator(const nlohmann::json& list, const std::string& name) {
  for (const nlohmann::json& e : list) {
    if (e.at("estimator") == name) return e;
  }
  ADD_FAILURE() << "no estimator " << name;
  static const nlohmann::json kNone;
  return kNone;
}

TEST(EvaluateCli, GeometryEqualsTheClosedForms) {
  const CommandResult run =
      Evaluate(std::string("simple butterfly --format json") + kSmallEvaluation);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j.at("patterns").size(), 2u);

  // Simple: the paper's sqrt(2 sigma^2) / d, d = 65 mm; the centroid bound sqrt(1/n + |pbar|^2 /
  // 2S) = sqrt(1/2 + 32.5^2 / (2 * 2112.5)) = sqrt(3)/2 per axis.
  const nlohmann::json& simple = j["patterns"][0]["geometry"];
  EXPECT_NEAR(simple["crlb_theta_rad_per_mm"].get<double>(), std::sqrt(2.0) / 65.0, 1e-12);
  EXPECT_NEAR(simple["crlb_position_mm_per_mm"].get<double>(), std::sqrt(3.0) / 2.0, 1e-12);
  const nlohmann::json& simple_fast = Estimator(simple["estimators"], "fast");
  EXPECT_NEAR(simple_fast["predicted_theta_rad_per_mm"].get<double>(), std::sqrt(2.0) / 65.0, 1e-7);
  EXPECT_NEAR(simple_fast["efficiency_theta"].get<double>(), 1.0, 1e-6);
  // The key estimator's position is one patch's sigma whatever the pattern.
  EXPECT_NEAR(Estimator(simple["estimators"], "key")["predicted_position_mm_per_mm"].get<double>(),
              1.0, 1e-6);

  // Butterfly (SSL geometry): four dots on a 65 mm circle around the key at x = 35 (twice) and
  // x = -54.772 (twice), n = 5: S = sum |p_i|^2 - n |pbar|^2.
  const nlohmann::json& butterfly = j["patterns"][1]["geometry"];
  const double pbar_x = (2.0 * 35.0 - 2.0 * 54.772) / 5.0;
  const double s = 4.0 * (35.0 * 35.0 + 54.772 * 54.772) - 5.0 * pbar_x * pbar_x;
  EXPECT_NEAR(butterfly["crlb_theta_rad_per_mm"].get<double>(), 1.0 / std::sqrt(s), 1e-6);
  const nlohmann::json& ml = Estimator(butterfly["estimators"], "ml");
  EXPECT_NEAR(ml["predicted_theta_rad_per_mm"].get<double>(),
              butterfly["crlb_theta_rad_per_mm"].get<double>(), 1e-7);
  EXPECT_NEAR(ml["predicted_position_mm_per_mm"].get<double>(),
              butterfly["crlb_position_mm_per_mm"].get<double>(), 1e-7);
  EXPECT_NEAR(ml["efficiency_theta"].get<double>(), 1.0, 1e-6);
  // The fast estimator weights the Butterfly's pairs by length: angle std 7.800 against the
  // bound's 7.765 mrad per mm (docs/paper-reproduction.md, Fig. 5), efficiency (7.765 / 7.800)^2 =
  // 0.991.
  EXPECT_NEAR(Estimator(butterfly["estimators"], "fast")["efficiency_theta"].get<double>(), 0.991,
              0.001);
}

TEST(EvaluateCli, MonteCarloMatchesThePrediction) {
  const CommandResult run =
      Evaluate("butterfly --format json --sigma 2 --trials 20000 --frames 1 --sigmas 1");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json mc = nlohmann::json::parse(run.out)["patterns"][0]["monte_carlo"];
  EXPECT_EQ(mc["trials"], 20000);
  EXPECT_EQ(mc["sigma_mm"], 2.0);
  ASSERT_EQ(mc["estimators"].size(), 4u);
  // A sample std's relative standard error is about 1 / sqrt(2 (n - 1)); allow 4 of them.
  const double tolerance = 4.0 / std::sqrt(2.0 * 20000);
  for (const nlohmann::json& e : mc["estimators"]) {
    EXPECT_NEAR(e["std_theta_rad"].get<double>() / e["predicted_theta_rad"].get<double>(), 1.0,
                tolerance)
        << e["estimator"];
    EXPECT_NEAR(e["std_position_mm"].get<double>() / e["predicted_position_mm"].get<double>(), 1.0,
                tolerance / std::sqrt(2.0) * 1.5)
        << e["estimator"];
    EXPECT_LT(e["std_theta_lo_rad"].get<double>(), e["std_theta_rad"].get<double>());
    EXPECT_GT(e["std_theta_hi_rad"].get<double>(), e["std_theta_rad"].get<double>());
  }
  // The prediction and the bound are per mm of sigma times sigma (docs/paper-reproduction.md: 7.765
  // mrad per mm).
  const nlohmann::json& ml = Estimator(mc["estimators"], "ml");
  EXPECT_NEAR(ml["crlb_theta_rad"].get<double>(), 2.0 * 7.765e-3, 1e-6);
  EXPECT_NEAR(ml["predicted_theta_rad"].get<double>(), ml["crlb_theta_rad"].get<double>(), 1e-9);
}

TEST(EvaluateCli, IdCountsAreTableTwo) {
  const CommandResult run =
      Evaluate("butterfly triangle --format json --trials 100 --frames 1 --sigmas 1");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  const auto counts = [&](int k) {
    std::vector<uint64_t> ids;
    for (const nlohmann::json& c : j["patterns"][k]["ids"]["counts"]) {
      ids.push_back(c["ids"].get<uint64_t>());
    }
    return ids;
  };
  EXPECT_EQ(counts(0), (std::vector<uint64_t>{16, 81, 256}));
  EXPECT_EQ(counts(1), (std::vector<uint64_t>{2, 8, 20}));
  EXPECT_EQ(j["patterns"][0]["ids"]["rotations"], 1);
  EXPECT_EQ(j["patterns"][1]["ids"]["rotations"], 3);
}

TEST(EvaluateCli, JsonHasEveryPart) {
  const CommandResult run =
      Evaluate("ssl-standard --format json --seed 7 --trials 4000 --frames 20 --sigmas 1,3");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["tool"], "patlab evaluate");
  EXPECT_EQ(j["seed"], 7);
  const nlohmann::json& p = j["patterns"][0];
  EXPECT_EQ(p["pattern"], "ssl-standard");
  EXPECT_EQ(p["patches"], 5);
  EXPECT_EQ(p["id_slots"], 4);
  for (const char* part : {"geometry", "monte_carlo", "ids", "misidentification"}) {
    EXPECT_TRUE(p.contains(part)) << part;
  }
  EXPECT_EQ(p["geometry"]["estimators"].size(), 4u);
  // The shipped codebook is used: 16 IDs of pink and green, 5 robots per team.
  const nlohmann::json& m = p["misidentification"];
  EXPECT_EQ(m["run"], true);
  EXPECT_NE(m["codebook"].get<std::string>().find("patterns/ssl-standard.codebook.toml"),
            std::string::npos);
  EXPECT_EQ(m["id_colours"], (nlohmann::json{"pink", "green"}));
  EXPECT_EQ(m["ids"], 16);
  EXPECT_EQ(m["robots_per_frame"], 10);
  ASSERT_EQ(m["points"].size(), 2u);
  const nlohmann::json& point = m["points"][1];
  EXPECT_EQ(point["sigma_mm"], 3.0);
  // The detector is told the noise level: patch_sigma_mm = max(2, sigma).
  EXPECT_EQ(m["points"][0]["detector_sigma_mm"], 2.0);
  EXPECT_EQ(point["detector_sigma_mm"], 3.0);
  EXPECT_EQ(point["robots"], 200);
  for (const char* rate : {"detection", "wrong_id_rate", "ambiguous_rate"}) {
    for (const char* field : {"rate", "lower", "upper", "count", "total"}) {
      EXPECT_TRUE(point[rate].contains(field)) << rate << " " << field;
    }
  }
  EXPECT_GT(point["detection"]["rate"].get<double>(), 0.9);
}

TEST(EvaluateCli, IdenticalForAnyThreadCount) {
  const std::string args = "butterfly triangle --trials 3000 --frames 30 --sigmas 2,4";
  const CommandResult one = Evaluate(args + " --threads 1");
  const CommandResult two = Evaluate(args + " --threads 2");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.out, two.out);
  EXPECT_NE(one.out.find("pattern butterfly"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("4. Misidentification"), std::string::npos) << one.out;
  // Another seed gives other Monte-Carlo numbers.
  EXPECT_NE(Evaluate(args + " --threads 2 --seed 2").out, one.out);
}

TEST(EvaluateCli, SymmetricTriangleIsNeverMisidentifiedAtSmallSigma) {
  const CommandResult run =
      Evaluate("triangle --format json --trials 100 --id-colors 4 --frames 200 --sigmas 0.5,1,2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json m = nlohmann::json::parse(run.out)["patterns"][0]["misidentification"];
  EXPECT_EQ(m["ids"], 20);
  for (const nlohmann::json& point : m["points"]) {
    EXPECT_EQ(point["wrong_id"], 0) << point["sigma_mm"];
    EXPECT_EQ(point["ambiguous"], 0) << point["sigma_mm"];
    EXPECT_EQ(point["wrong_id_rate"]["lower"], 0.0);
    EXPECT_GT(point["correct"].get<int>(), 1990) << point["sigma_mm"];
  }
}

TEST(EvaluateCli, TextReportHasTheFourParts) {
  const CommandResult run = Evaluate(std::string("triangle") + kSmallEvaluation);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* line :
       {"pattern triangle (patterns/triangle.toml): 4 patches, 3 ID slots\n",
        "1. Accuracy from geometry", "2. Accuracy by Monte-Carlo at sigma = 1 mm (4000 trials",
        "3. ID capacity (paper Table II; symmetry tolerance 10 mm)\n"
        "   3 rotations about the key that geometry cannot tell apart: colours decide\n",
        "   IDs                 2         8        20\n",
        "4. Misidentification in whole frames (2 IDs of pink, green)\n",
        "   20 frames per sigma, 4 robots per frame"}) {
    EXPECT_NE(run.out.find(line), std::string::npos) << line << "\n---\n" << run.out;
  }
}

TEST(EvaluateCli, BadInputExitsTwoWithMessage) {
  const auto expect = [](const std::string& args, const std::string& message) {
    const CommandResult run = Evaluate(args);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_EQ(run.out, "") << args;
    EXPECT_EQ(run.err, message) << args;
  };
  expect("hexagon",
         "patlab evaluate: pattern 'hexagon' not found; expected an existing file or a name "
         "in " PATLAB_SOURCE_DIR "/patterns/\n");
  expect("butterfly hexagon --trials 2",
         "patlab evaluate: pattern 'hexagon' not found; expected an existing file or a name "
         "in " PATLAB_SOURCE_DIR "/patterns/\n");
  expect("butterfly --sigma -1",
         "patlab evaluate: --sigma is -1; expected a patch std in mm > 0\n");
  expect("butterfly --sigma 0", "patlab evaluate: --sigma is 0; expected a patch std in mm > 0\n");
  expect("butterfly --colors 2,x",
         "patlab evaluate: --colors has 'x'; expected comma-separated integers from 1 to 16, e.g. "
         "2,3,4\n");
  expect("butterfly --colors 0",
         "patlab evaluate: --colors has '0'; expected comma-separated integers from 1 to 16, e.g. "
         "2,3,4\n");
  expect("butterfly --sigmas 2,1",
         "patlab evaluate: --sigmas has 1; expected strictly increasing finite numbers >= 0 "
         "(mm)\n");
  expect("butterfly --trials 1",
         "patlab evaluate: --trials is 1; expected an integer in [2, 1000000000]\n");
  expect("butterfly --frames 0",
         "patlab evaluate: --frames is 0; expected an integer in [1, 100000000]\n");
  expect("butterfly --id-colors 9",
         "patlab evaluate: --id-colors is 9; expected an integer in [1, 8]\n");
  expect("butterfly --id-colors 0",
         "patlab evaluate: --id-colors is 0; expected an integer in [1, 8]\n");
  expect("butterfly --tolerance -1",
         "patlab evaluate: --tolerance is -1; expected a distance in mm >= 0\n");
  expect("butterfly --seed -4", "patlab evaluate: --seed is '-4'; expected an integer >= 0\n");
  expect("butterfly --threads -1",
         "patlab evaluate: --threads is -1; expected 0 (all cores) to 4096\n");
  expect("",
         "patlab evaluate: missing PATTERN; expected 'patlab evaluate PATTERN... [options]' "
         "(see --help)\n");
}

TEST(EvaluateCli, HelpListsOptionsAndExamples) {
  const CommandResult run = Evaluate("--help");
  EXPECT_EQ(run.exit_code, 0);
  for (const char* text :
       {"--sigma", "--trials", "--colors", "--tolerance", "--sigmas", "--id-colors", "--frames",
        "--seed", "--threads", "--format", "patlab evaluate butterfly"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace patlab

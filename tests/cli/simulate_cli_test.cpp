// End-to-end tests of `patlab simulate`: the real binary, real files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kPatlab;
using testing::RunCommand;
using testing::SmallExperiment;

TEST(SimulateCli, HelpShowsExamplesAndExitsZero) {
  const auto r = RunCommand(kPatlab + " simulate --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("examples:"), std::string::npos);
  EXPECT_NE(r.out.find("--threads"), std::string::npos);
}

TEST(SimulateCli, WritesTidyCsvAndManifestIdenticalForAnyThreadCount) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("small.toml", SmallExperiment());
  const auto one =
      RunCommand(kPatlab + " simulate " + experiment + " --threads 1 -q --out " + dir.Path("one"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto two =
      RunCommand(kPatlab + " simulate " + experiment + " --threads 2 -q --out " + dir.Path("two"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const std::string csv = testing::ReadFile(dir.Path("one/small.csv"));
  EXPECT_EQ(csv, testing::ReadFile(dir.Path("two/small.csv")));
  // Header + 2 patterns x 3 estimators x 3 sigmas.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 3 * 3);
  EXPECT_EQ(csv.rfind("pattern,estimator,sigma_mm,trials,noise,", 0), 0u);
  EXPECT_NE(csv.find(",rms_radial_mm,mean_radial_mm,std_radial_mm,std_radial_lo_mm,"),
            std::string::npos);
  EXPECT_NE(csv.find("\nbutterfly,ml,2,3000,isotropic,"), std::string::npos);

  const auto manifest = nlohmann::json::parse(testing::ReadFile(dir.Path("one/small.json")));
  EXPECT_EQ(manifest["seed"], 77);
  EXPECT_EQ(manifest["trials_per_point"], 3000);
  EXPECT_EQ(manifest["patterns"].size(), 2u);
  EXPECT_EQ(manifest["outputs"], nlohmann::json::array({"small.csv", "small.json"}));
  // Nothing of the run itself: the same results give the same manifest on any machine.
  for (const char* key : {"threads", "timings_s", "command_line", "trials_per_second"}) {
    EXPECT_FALSE(manifest.contains(key)) << key;
  }
  // No temporary files are left behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.Path("one"))) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 2);
}

TEST(SimulateCli, OverridesTakeEffect) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("small.toml", SmallExperiment());
  const auto r = RunCommand(kPatlab + " simulate " + experiment +
                            " -q --trials 500 --seed 3 --sigmas 1 --common-sigma-ratio 0.5 --out " +
                            dir.Path("o"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = testing::ReadFile(dir.Path("o/small.csv"));
  EXPECT_NE(csv.find("\nlinear,fast,1,500,isotropic+common,"), std::string::npos) << csv;
}

TEST(SimulateCli, BadInputExitsTwoWithAMessageAndWritesNothing) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("small.toml", SmallExperiment());
  const std::string out = " -q --out " + dir.Path("out");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {kPatlab + " simulate " + dir.Path("missing.toml") + out,
       "patlab simulate: " + dir.Path("missing.toml") +
           ": cannot open file; expected a readable TOML file\n"},
      {kPatlab + " simulate " + experiment + " --trials 1" + out,
       "patlab simulate: --trials is 1; expected an integer in [2, 1000000000]\n"},
      {kPatlab + " simulate " + experiment + " --seed -4" + out,
       "patlab simulate: --seed is '-4'; expected an integer >= 0\n"},
      {kPatlab + " simulate " + experiment + " --sigmas 1,x" + out,
       "patlab simulate: --sigmas has 'x'; expected comma-separated numbers, e.g. 0,0.5,1\n"},
      {kPatlab + " simulate " + experiment + " --outlier-probability 2" + out,
       "patlab simulate: noise options: outlier_probability is 2; expected a probability in [0, "
       "1)\n"},
      {kPatlab + " simulate" + out,
       "patlab simulate: missing EXPERIMENT; expected 'patlab simulate EXPERIMENT' (see --help)\n"},
      {kPatlab + " simulate " + experiment + " --no-such-flag" + out,
       "patlab simulate: unknown option --no-such-flag; expected an option that 'patlab help "
       "simulate' lists\n"},
  };
  for (const auto& [command, message] : cases) {
    const auto r = RunCommand(command);
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_EQ(r.err, message) << command;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
}

TEST(SimulateCli, UnwritableOutputFailsWithoutPartialFiles) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("small.toml", SmallExperiment());
  dir.Write("blocker", "a file where the output directory should be");
  const auto r = RunCommand(kPatlab + " simulate " + experiment + " -q --trials 100 --out " +
                            dir.Path("blocker/sub"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
}

TEST(SimulateCli, ReplayReproducesATrial) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("small.toml", SmallExperiment());
  const auto r = RunCommand(kPatlab + " simulate " + experiment + " --replay 5,123");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("point 5 (pattern butterfly, sigma 2 mm), trial 123, seed 77"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("ml summary converged"), std::string::npos) << r.out;
  const auto bad = RunCommand(kPatlab + " simulate " + experiment + " --replay 6,0");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err,
            "patlab simulate: --replay 6,0 is out of range; expected POINT < 6 and TRIAL < 3000\n");
}

TEST(Cli, UnknownCommandAndNoArgumentsExitTwo) {
  EXPECT_EQ(RunCommand(kPatlab + " frobnicate").exit_code, 2);
  EXPECT_EQ(RunCommand(kPatlab).exit_code, 2);
  const auto help = RunCommand(kPatlab + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("simulate"), std::string::npos);
}

}  // namespace
}  // namespace patlab

namespace patlab {
namespace {

using testing::RunCommand;

// SIGTERM during a run ends it with no result and no temporary file (SIGINT acts the same, but a
// background job of a non-interactive shell ignores it).
TEST(SimulateCliHardening, InterruptedRunLeavesNothing) {
  testing::TempDir dir;
  const std::string experiment =
      dir.Write("e.toml", "name = \"e\"\npatterns_dir = \"" PATLAB_SOURCE_DIR
                          "/patterns\"\npatterns = [\"butterfly\"]\ntrials = 1000000\n[sigma]\n"
                          "from = 0\nto = 4\nsteps = 400\n");
  dir.Write("out/old.txt", "untouched");
  // Appended piece by piece: GCC 12's -Wrestrict misfires on "(" + std::string under -Werror.
  std::string command = "(";
  command.append(PATLAB_BINARY).append(" simulate ").append(experiment);
  command.append(" -q --threads 1 --out ").append(dir.Path("out"));
  command.append(" & pid=$!; sleep 1; kill -TERM $pid; wait $pid; echo status $?)");
  const auto r = RunCommand(command);
  EXPECT_EQ(r.out, "status 143\n") << r.err;
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.Path("out"))) {
    names.insert(e.path().filename().string());
  }
  EXPECT_EQ(names, std::set<std::string>{"old.txt"});
}

}  // namespace
}  // namespace patlab

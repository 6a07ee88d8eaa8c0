// End-to-end tests of `patlab track`: the real binary, real files.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kPatlab;
using testing::RunCommand;

std::string TinyExperiment() {
  return "name = \"tiny\"\nseed = 5\nruns = 2\ndiameters_mm = [40, 60]\n"
         "pattern = \"butterfly\"\npatterns_dir = \"" PATLAB_SOURCE_DIR
         "/patterns\"\n"
         "[platform]\nsamples_per_run = 120\n[analysis]\ntrim_samples = 20\n"
         "[noise]\npixel_sigma = 8\njitter_sigma_px = 0.05\n";
}

TEST(TrackCli, HelpShowsExamplesAndExitsZero) {
  const auto r = RunCommand(kPatlab + " track --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("examples:"), std::string::npos);
  EXPECT_NE(r.out.find("--threads"), std::string::npos);
  EXPECT_NE(r.out.find("patlab track table1"), std::string::npos);
}

TEST(TrackCli, WritesTableTestsErrorsAndManifestIdenticalForAnyThreadCount) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("tiny.toml", TinyExperiment());
  const auto one =
      RunCommand(kPatlab + " track " + experiment + " --threads 1 --out " + dir.Path("one"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.err.find("wrote "), std::string::npos);
  const auto two =
      RunCommand(kPatlab + " track " + experiment + " --threads 2 -q --out " + dir.Path("two"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(two.err, "");
  for (const char* file : {"tiny.csv", "tiny_tests.csv", "track_errors.csv"}) {
    EXPECT_EQ(testing::ReadFile(dir.Path(std::string("one/") + file)),
              testing::ReadFile(dir.Path(std::string("two/") + file)))
        << file;
  }
  const std::string table = testing::ReadFile(dir.Path("one/tiny.csv"));
  // Header + 40mm, 60mm, butterfly.
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 4);
  EXPECT_NE(table.find("\n40mm,160,"), std::string::npos) << table;
  EXPECT_NE(table.find("\nbutterfly,160,"), std::string::npos) << table;
  const std::string tests = testing::ReadFile(dir.Path("one/tiny_tests.csv"));
  // Header + {est, true} x {x, y, xy} x one pair.
  EXPECT_EQ(std::count(tests.begin(), tests.end(), '\n'), 1 + 6);
  EXPECT_NE(tests.find("\nest,x,40mm,60mm,160,"), std::string::npos) << tests;
  const std::string errors = testing::ReadFile(dir.Path("one/track_errors.csv"));
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1 + 3 * 2 * 80);

  const auto manifest = nlohmann::json::parse(testing::ReadFile(dir.Path("one/tiny.json")));
  EXPECT_EQ(manifest["seed"], 5);
  EXPECT_FALSE(manifest.contains("threads"));
  EXPECT_EQ(manifest["run_setups"].size(), 2u);
  EXPECT_EQ(manifest["table"].size(), 3u);
  EXPECT_TRUE(manifest["table"][2].contains("true_theta"));
  EXPECT_FALSE(manifest.contains("timings_s"));
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.Path("one"))) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 4);  // no temporary files left behind
}

TEST(TrackCli, OverridesTakeEffect) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("tiny.toml", TinyExperiment());
  ASSERT_EQ(RunCommand(kPatlab + " track " + experiment + " -q --out " + dir.Path("a")).exit_code,
            0);
  const auto r =
      RunCommand(kPatlab + " track " + experiment +
                 " -q --seed 6 --pixel-sigma 0 --jitter-px 0 --decimate 8 --out " + dir.Path("b"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::ReadFile(dir.Path("a/tiny.csv")), testing::ReadFile(dir.Path("b/tiny.csv")));
  const auto manifest = nlohmann::json::parse(testing::ReadFile(dir.Path("b/tiny.json")));
  EXPECT_EQ(manifest["seed"], 6);
  EXPECT_EQ(manifest["noise"]["pixel_sigma"], 0.0);
  const std::string errors = testing::ReadFile(dir.Path("b/track_errors.csv"));
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1 + 3 * 2 * 20);
}

TEST(TrackCli, ReplayPrintsOneFrame) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("tiny.toml", TinyExperiment());
  const auto r = RunCommand(kPatlab + " track " + experiment + " --replay 1,50");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("run 1, frame 50, seed 5: heading ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("\n40mm       truth ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("theta error "), std::string::npos) << r.out;
  const auto bad = RunCommand(kPatlab + " track " + experiment + " --replay 2,0");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err,
            "patlab track: --replay 2,0 is out of range; expected RUN < 2 and FRAME < 120\n");
  const auto junk = RunCommand(kPatlab + " track " + experiment + " --replay 1");
  EXPECT_EQ(junk.err, "patlab track: --replay is '1'; expected RUN,FRAME (two integers >= 0)\n");
}

TEST(TrackCli, BadInputExitsTwoWithAMessageAndWritesNothing) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("tiny.toml", TinyExperiment());
  const std::string bad = dir.Write("bad.toml", "runs = 2\n[noise]\npixel_sigma = -3\n");
  const std::string out = " -q --out " + dir.Path("out");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {kPatlab + " track " + dir.Path("missing.toml") + out,
       "patlab track: " + dir.Path("missing.toml") +
           ": cannot open file; expected a readable TOML file\n"},
      {kPatlab + " track " + bad + out,
       "patlab track: " + bad +
           ":3: noise.pixel_sigma is -3; expected a finite number >= 0 (grey levels)\n"},
      {kPatlab + " track " + experiment + " --seed x1" + out,
       "patlab track: --seed is 'x1'; expected an integer >= 0\n"},
      {kPatlab + " track " + experiment + " --threads -1" + out,
       "patlab track: --threads is -1; expected 0 (all cores) to 4096\n"},
      {kPatlab + " track " + experiment + " --decimate 0" + out,
       "patlab track: --decimate is 0; expected an integer >= 1\n"},
      {kPatlab + " track " + experiment + " --jitter-px -1" + out,
       "patlab track: after the command-line overrides: noise.jitter_sigma_px is -1; "
       "expected a finite number >= 0 (px)\n"},
      {kPatlab + " track" + out,
       "patlab track: missing EXPERIMENT; expected 'patlab track EXPERIMENT' (see --help)\n"},
      {kPatlab + " track " + experiment + " --no-such-flag" + out,
       "patlab track: unknown option --no-such-flag; expected an option that 'patlab help track' "
       "lists\n"},
  };
  for (const auto& [command, message] : cases) {
    const auto r = RunCommand(command);
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_EQ(r.err, message) << command;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
}

TEST(TrackCli, UnwritableOutputFailsWithExitOne) {
  testing::TempDir dir;
  const std::string experiment = dir.Write("tiny.toml", TinyExperiment());
  dir.Write("blocker", "a file where the output directory should be");
  const auto r =
      RunCommand(kPatlab + " track " + experiment + " -q --out " + dir.Path("blocker/sub"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace patlab

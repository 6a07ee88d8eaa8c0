// The one progress reporter (src/cli/progress.h, docs/cli.md "Progress") in every command that
// gained it, end to end: with PATLAB_PROGRESS=always (no quiet first second) each reports the
// library's own count up to done = total on stderr, as the log form (stderr is a file here: one
// line per 10%); without it a short run prints no progress line; -q silences it even when forced.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "../test_util.h"
#include "cli/progress.h"
#include "patlab/core/format.h"

namespace patlab::cli {
namespace {

using testing::kGoldenFrame;
using testing::kPatlab;
using testing::kSource;
using testing::RunCommand;

// The stderr lines that start with `prefix`.
std::vector<std::string> LinesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

// Runs `args` three ways (forced, forced with -q, not forced) and checks the progress lines:
// forced, the last one is "<command>: <total>/<total> <unit> (100%), ..."; -q prints none, and
// neither does an unforced run when `short_run` (one that may take over a second reports, as it
// should, so it is not run unforced).
void ExpectProgress(const std::string& dir, const std::string& command, const std::string& args,
                    const std::string& done, const std::string& unit, bool short_run = true) {
  const std::string prefix = "patlab " + command + ": ";
  const std::string run = "cd " + dir + " && ";
  const auto forced =
      RunCommand(run + "PATLAB_PROGRESS=always " + kPatlab + " " + command + " " + args);
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  const std::vector<std::string> lines = LinesStartingWith(forced.err, prefix + "");
  std::vector<std::string> progress;
  for (const std::string& line : lines) {
    if (line.find(" " + unit + " (") != std::string::npos) progress.push_back(line);
  }
  ASSERT_FALSE(progress.empty()) << forced.err;
  EXPECT_EQ(progress.back().rfind(prefix + done + "/" + done + " " + unit + " (100%), ", 0), 0u)
      << forced.err;
  EXPECT_NE(progress.back().find(" elapsed"), std::string::npos) << progress.back();
  EXPECT_LE(progress.size(), 11u) << forced.err;  // the log form: one line per 10% at most

  const auto quiet =
      RunCommand(run + "PATLAB_PROGRESS=always " + kPatlab + " " + command + " " + args + " -q");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find(" " + unit + " ("), std::string::npos) << quiet.err;

  if (!short_run) return;
  // The quiet first second is the process's own: a run that took under a second from launch to
  // exit cannot have reported. One that took longer (a loaded machine, a sanitized build) may,
  // as it should, so the check holds only for the former.
  const auto start = std::chrono::steady_clock::now();
  const auto plain = RunCommand(run + kPatlab + " " + command + " " + args);
  const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  if (took.count() < Progress::kQuietSeconds) {
    EXPECT_EQ(plain.err.find(" " + unit + " ("), std::string::npos) << plain.err;
  }
}

TEST(ProgressCli, DetectCountsFrames) {
  testing::TempDir dir;
  const std::string png = kGoldenFrame + "png";
  ExpectProgress(dir.Path(), "detect",
                 png + " " + png + " " + png + " -t " + kGoldenFrame + "thresholds.toml -c " +
                     kGoldenFrame + "calibration.toml -s " + kGoldenFrame + "detector.toml -o d",
                 "3", "frames");
}

TEST(ProgressCli, AnalyzeCountsSubjects) {
  testing::TempDir dir;
  // Three subjects on straight lines with a deterministic wobble, 100 frames each.
  std::string csv = "frame,subject,x_mm,y_mm\n";
  for (const char* subject : {"a", "b", "c"}) {
    for (int f = 0; f < 100; ++f) {
      const double wobble = std::sin(7.3 * f + subject[0]) * 0.5;
      csv += std::to_string(f) + "," + subject + "," + FormatFixed(10.0 * f + wobble, 3) + "," +
             FormatFixed(wobble * 0.7, 3) + "\n";
    }
  }
  dir.Write("track.csv", csv);
  ExpectProgress(dir.Path(), "analyze", "track.csv -o a", "3", "subjects");
}

TEST(ProgressCli, MergeCountsShardFiles) {
  testing::TempDir dir;
  dir.Write("small.toml", "name = \"small\"\npatterns_dir = \"" + kSource +
                              "/patterns\"\npatterns = [\"linear\"]\nestimators = [\"fast\"]\n"
                              "trials = 200\nseed = 5\n[sigma]\nvalues = [0.5, 1]\n");
  for (const char* k : {"1/3", "2/3", "3/3"}) {
    const auto s = RunCommand("cd " + dir.Path() + " && " + kPatlab +
                              " simulate small.toml -q --shard " + k + " -o shards");
    ASSERT_EQ(s.exit_code, 0) << s.err;
  }
  ExpectProgress(dir.Path(), "merge", "shards -o merged", "3", "shard files");
}

TEST(ProgressCli, DesignCountsStarts) {
  testing::TempDir dir;
  ExpectProgress(dir.Path(), "design", "--starts 4 --max-evaluations 30 -o d", "4", "starts");
}

TEST(ProgressCli, CamtrackCountsFrames) {
  testing::TempDir dir;
  ExpectProgress(dir.Path(), "camtrack",
                 kSource + "/experiments/camera-noise/track-scene.toml -t " + kSource +
                     "/experiments/camera-noise/track.thresholds.toml --runs 2 --frames 5 -o c",
                 "10", "frames");
}

// The study's steps (docs/cli.md): the fit (1), its 2 profiled magnitudes, 3 bootstrap
// replicates, the 9 candidate models of models.csv and 2 sensitivity fits for the one radius.
TEST(ProgressCli, FitnoiseCountsSteps) {
  testing::TempDir dir;
  ExpectProgress(dir.Path(), "fitnoise",
                 "--free independent_x_mm,independent_y_mm --bootstrap 3 --profile-points 3 "
                 "--sensitivity-radii 50 --simulate-runs 0 -o f",
                 "17", "steps", false);
}

}  // namespace
}  // namespace patlab::cli

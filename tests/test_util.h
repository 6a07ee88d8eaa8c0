// Shared helpers for the tests: the shipped patterns, temporary files, running the CLI.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "expect_error.h"
#include "patlab/core/pattern.h"
#include "patlab/formats/pattern_file.h"

namespace patlab::testing {

// The tool the end-to-end tests run, and the repository's files the tests read. A room's test
// files compile as one translation unit (tests/CMakeLists.txt): what several of them share is
// defined here once.
inline const std::string kPatlab = PATLAB_BINARY;
inline const std::string kSource = PATLAB_SOURCE_DIR;
inline const std::string kData = kSource + "/tests/data/";
inline const std::string kGolden = kData + "golden/";
// The golden SSL frame's files: kGoldenFrame + "png", + "thresholds.toml", ...
inline const std::string kGoldenFrame = kGolden + "ssl-frame.";

// The size of the frames the calibration and vision tests render: an SSL camera's.
inline constexpr int kFrameWidth = 780, kFrameHeight = 580;

inline constexpr double kPi = std::numbers::pi;

// A small experiment file for the tool's end-to-end runs (`patlab simulate`, `patlab merge`): two
// shipped patterns, three estimators, three sigmas, 3000 trials a point.
inline std::string SmallExperiment() {
  return "name = \"small\"\npatterns_dir = \"" PATLAB_SOURCE_DIR
         "/patterns\"\n"
         "patterns = [\"linear\", \"butterfly\"]\nestimators = [\"fast\", \"ml\", \"key\"]\n"
         "trials = 3000\nseed = 77\n[sigma]\nvalues = [0, 0.5, 2]\n";
}

inline const std::vector<std::string>& ShippedPatternNames() {
  static const std::vector<std::string> names = {"simple", "linear", "triangle", "butterfly",
                                                 "ssl-standard"};
  return names;
}

inline Pattern ShippedPattern(const std::string& name) {
  return formats::LoadPatternFile(std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name + ".toml");
}

// A fresh empty directory under the system temp dir, removed by the destructor.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("patlab_test_" + std::to_string(rd()) + "_" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string Write(const std::string& name, const std::string& content) const {
    const auto p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
  std::string Path(const std::string& name = "") const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The names of the entries of `dir` (not recursive).
inline std::set<std::string> FileNames(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.insert(e.path().filename().string());
  return names;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `command` through the shell with stdout and stderr captured.
inline CommandResult RunCommand(const std::string& command) {
  TempDir dir;
  const std::string out = dir.Path("stdout"), err = dir.Path("stderr");
  const int status = std::system((command + " >" + out + " 2>" + err).c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadFile(out);
  r.err = ReadFile(err);
  return r;
}

}  // namespace patlab::testing

// Shared helpers for the tests: the shipped patterns, temporary files, running the CLI.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "expect_error.h"
#include "patlab/core/pattern.h"
#include "patlab/formats/pattern_file.h"

namespace patlab::testing {

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

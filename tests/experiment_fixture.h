// A scratch tree for experiment-file tests: <dir>/patterns/ holds copies of shipped patterns,
// <dir>/experiments/e.toml the experiment under test, as in the repository.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "patlab/core/error.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/experiment.h"
#include "test_util.h"

namespace patlab::sim::testing_support {

class ExperimentFixture : public ::testing::Test {
 protected:
  void CopyPatterns(std::initializer_list<const char*> names) {
    for (const char* name : names) {
      dir_.Write(std::string("patterns/") + name + ".toml",
                 patlab::testing::ReadFile(std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name +
                                           ".toml"));
    }
  }
  std::string Write(const std::string& text) { return dir_.Write("experiments/e.toml", text); }
  // LoadExperimentFile must reject `text` with `message`, word for word; a message that does
  // not start with '/' names a file of the scratch experiments/ ("e.toml:3: ...").
  void ExpectLoadError(const std::string& text, const std::string& message) {
    SCOPED_TRACE(text);
    const std::string path = Write(text);
    const std::string full =
        message.starts_with("/") ? message : dir_.Path("experiments/") + message;
    EXPECT_INPUT_ERROR(formats::LoadExperimentFile(path), full);
  }
  patlab::testing::TempDir dir_;
};

}  // namespace patlab::sim::testing_support

// A scratch tree for experiment-file tests: <dir>/patterns/ holds copies of shipped patterns,
// <dir>/experiments/e.toml the experiment under test, as in the repository.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/sim/experiment.h"

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
  // The message LoadExperimentFile gives for `text`, with the scratch experiments/ prefix cut so
  // that messages read "e.toml:3: ..."; "(no error)" if it loads.
  std::string ErrorOf(const std::string& text) {
    const std::string path = Write(text);
    try {
      LoadExperimentFile(path);
    } catch (const InputError& e) {
      std::string message = e.what();
      const std::string prefix = dir_.Path("experiments/");
      if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
      return message;
    }
    return "(no error)";
  }
  patlab::testing::TempDir dir_;
};

}  // namespace patlab::sim::testing_support

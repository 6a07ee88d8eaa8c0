// Overrides of an experiment from the command line (sim/experiment.h ApplyOverrides), checked
// as the experiment file's own values are (tests/formats/experiment_file_test.cpp).
#include "patlab/sim/experiment.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/core/error.h"

namespace patlab::sim {
namespace {

TEST(Overrides, AreValidatedLikeTheFile) {
  Experiment e;
  e.sigmas_mm = {1.0};
  Overrides o;
  o.trials = 1;
  EXPECT_INPUT_ERROR(ApplyOverrides(o, &e),
                     "--trials is 1; expected an integer in [2, 1000000000]");
  o = Overrides{};
  o.sigmas_mm = {1.0, 1.0};
  EXPECT_INPUT_ERROR(ApplyOverrides(o, &e),
                     "--sigmas has 1; expected strictly increasing finite numbers >= 0 (mm)");
}

}  // namespace
}  // namespace patlab::sim

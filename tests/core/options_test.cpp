// Tests of the options validation idiom (src/patlab/core/options.h).
#include "patlab/core/options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "../expect_error.h"

namespace patlab {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The message of the one problem `check` holds.
std::string OnlyMessage(const OptionsChecker& check) {
  EXPECT_EQ(check.problems().size(), 1u);
  return check.problems().empty() ? "" : check.problems().front().message;
}

TEST(OptionsChecker, PositiveNamesTheFieldValueAndUnit) {
  EXPECT_TRUE(OptionsChecker().Positive("sigma_mm", 0.5, "mm").problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().Positive("sigma_mm", 0.0, "mm")),
            "sigma_mm is 0; expected a finite number > 0 (mm)");
  EXPECT_EQ(OnlyMessage(OptionsChecker().Positive("sigma_mm", kInf)),
            "sigma_mm is inf; expected a finite number > 0");
  EXPECT_EQ(OnlyMessage(OptionsChecker().Positive("sigma_mm", kNan)),
            "sigma_mm is nan; expected a finite number > 0");
}

TEST(OptionsChecker, NonNegativeAcceptsZero) {
  EXPECT_TRUE(OptionsChecker().NonNegative("jitter_px", 0.0, "px").problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().NonNegative("jitter_px", -1.5, "px")),
            "jitter_px is -1.5; expected a finite number >= 0 (px)");
  EXPECT_EQ(OnlyMessage(OptionsChecker().NonNegative("jitter_px", kInf)),
            "jitter_px is inf; expected a finite number >= 0");
}

TEST(OptionsChecker, InRangeIsClosed) {
  OptionsChecker ok;
  ok.InRange("heading_max_deg", 0.0, 0.0, 45.0).InRange("heading_max_deg", 45.0, 0.0, 45.0);
  EXPECT_TRUE(ok.problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().InRange("heading_max_deg", 46.0, 0.0, 45.0, "degrees")),
            "heading_max_deg is 46; expected a number in [0, 45] (degrees)");
  EXPECT_EQ(OnlyMessage(OptionsChecker().InRange("heading_max_deg", kNan, 0.0, 45.0)),
            "heading_max_deg is nan; expected a number in [0, 45]");
}

TEST(OptionsChecker, InOpenRangeExcludesTheEnds) {
  EXPECT_TRUE(OptionsChecker().InOpenRange("level", 0.95, 0.0, 1.0).problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().InOpenRange("level", 1.0, 0.0, 1.0)),
            "level is 1; expected a number in (0, 1)");
  EXPECT_EQ(OnlyMessage(OptionsChecker().InOpenRange("p", 0.0, 0.0, 1.0, "a probability")),
            "p is 0; expected a probability in (0, 1)");
}

TEST(OptionsChecker, IntegerInRangeIsClosed) {
  OptionsChecker ok;
  ok.IntegerInRange("runs", 1, 1, 1000).IntegerInRange("runs", 1000, 1, 1000);
  EXPECT_TRUE(ok.problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().IntegerInRange("runs", 0, 1, 1000)),
            "runs is 0; expected an integer in [1, 1000]");
  EXPECT_EQ(OnlyMessage(OptionsChecker().IntegerInRange("seed", -9000000000, 0, 5)),
            "seed is -9000000000; expected an integer in [0, 5]");
}

TEST(OptionsChecker, RequireAndFail) {
  EXPECT_TRUE(OptionsChecker().Require("x", 1.0, true, "anything").problems().empty());
  EXPECT_EQ(OnlyMessage(OptionsChecker().Require("threshold", 30, false, "above the floor")),
            "threshold is 30; expected above the floor");
  const OptionsChecker fail = std::move(OptionsChecker("subjects").Fail("diameters_mm", "empty"));
  ASSERT_EQ(fail.problems().size(), 1u);
  EXPECT_EQ(fail.problems()[0].field, "subjects.diameters_mm");
  EXPECT_EQ(fail.problems()[0].message, "empty");  // Fail's message is taken as it is
}

TEST(OptionsChecker, TablePrefixesFieldAndMessage) {
  OptionsChecker check("camera");
  EXPECT_EQ(check.Name("height_mm"), "camera.height_mm");
  check.Positive("height_mm", -1.0, "mm");
  ASSERT_EQ(check.problems().size(), 1u);
  EXPECT_EQ(check.problems()[0].field, "camera.height_mm");
  EXPECT_EQ(check.problems()[0].message,
            "camera.height_mm is -1; expected a finite number > 0 (mm)");
  EXPECT_EQ(OptionsChecker().Name("runs"), "runs");
}

TEST(OptionsChecker, TakeReturnsEveryProblemInCheckOrderAndEmptiesTheChecker) {
  OptionsChecker check;
  check.Positive("a", 0.0).Positive("b", 1.0).NonNegative("c", -1.0).IntegerInRange("d", 9, 0, 1);
  const std::vector<OptionsProblem> problems = check.Take();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].field, "a");
  EXPECT_EQ(problems[1].field, "c");
  EXPECT_EQ(problems[2].field, "d");
  EXPECT_TRUE(check.problems().empty());
}

TEST(ThrowFirstProblem, ThrowsTheFirstMessageOnly) {
  ThrowFirstProblem({});  // nothing to throw
  EXPECT_INPUT_ERROR(ThrowFirstProblem({{"a", "first"}, {"b", "second"}}), "first");
}

}  // namespace
}  // namespace patlab

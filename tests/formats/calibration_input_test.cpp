// Calibration inputs (formats/calibration_input.h): features read by name and coordinates, and
// every bad input's message, word for word.
#include "patlab/formats/calibration_input.h"

#include <gtest/gtest.h>

#include <string>

#include "../expect_error.h"
#include "patlab/core/error.h"

namespace patlab::formats {
namespace {

calib::CalibrationInput ParseInput(const std::string& text) {
  return ParseCalibrationInput(text, "in.toml", std::string(PATLAB_SOURCE_DIR) + "/experiments");
}

TEST(CalibrationInput, ReadsFeaturesByNameAndCoordinates) {
  const calib::CalibrationInput in = ParseInput(R"(
image_size_px = [780, 580]
field = "fields/ssl-2009.toml"
[fit]
fix = ["k2", "principal_point"]
focal_px = 850
[heights]
default_mm = 140
orange = 21.5
[[point]]
feature = "centre"
pixel = [390, 290]
[[point]]
world_mm = [100, 200]
height_mm = 150
pixel = [10, 20]
[[line]]
feature = "halfway"
pixels = [[1, 2], [3, 4]]
[[circle]]
centre_mm = [0, 0]
radius_mm = 500
pixels = [[5, 6]]
[[pattern]]
pattern = "../patterns/ssl-standard.toml"
height_mm = 150
pixels = [[1, 1], "missing", [2, 2], [3, 3], [4, 4]]
)");
  ASSERT_EQ(in.points.size(), 2u);
  EXPECT_EQ(in.points[0].name, "centre");
  EXPECT_EQ(in.points[1].world_mm, Vec2(100, 200));
  EXPECT_EQ(in.points[1].height_mm, 150.0);
  EXPECT_EQ(in.points[1].loc.line, 13);
  ASSERT_EQ(in.lines.size(), 1u);
  EXPECT_EQ(in.lines[0].to_mm, Vec2(0, 2025));
  EXPECT_EQ(in.circles[0].radius_mm, 500.0);
  ASSERT_EQ(in.patterns[0].pixels.size(), 5u);
  EXPECT_FALSE(in.patterns[0].pixels[1].has_value());
  EXPECT_EQ(in.options.fixed.size(), 2u);
  EXPECT_EQ(in.options.focal_px.value_or(0), 850.0);
  EXPECT_EQ(in.class_height_mm.at("orange"), 21.5);
}

TEST(CalibrationInput, BadInputSaysWhereAndWhatWasExpected) {
  const std::string head = "image_size_px = [780, 580]\nfield = \"fields/ssl-2009.toml\"\n";
  EXPECT_INPUT_ERROR(ParseInput(head + "[[point]]\nfeature = \"middle\"\npixel = [1, 2]\n"),
                     "in.toml:4: point feature 'middle' is not in field 'ssl-2009'; expected one "
                     "of: centre, corner_pos_left, corner_pos_right, corner_neg_left, "
                     "corner_neg_right, halfway_left, halfway_right, centre_circle_left, "
                     "centre_circle_right, defense_front_left_pos, defense_front_right_pos, "
                     "defense_goal_left_pos, defense_goal_right_pos, defense_front_left_neg, "
                     "defense_front_right_neg, defense_goal_left_neg, defense_goal_right_neg, "
                     "goal_post_left_pos, goal_post_right_pos, goal_back_left_pos, "
                     "goal_back_right_pos, goal_post_left_neg, goal_post_right_neg, "
                     "goal_back_left_neg, goal_back_right_neg, penalty_mark_pos, "
                     "penalty_mark_neg");
  EXPECT_INPUT_ERROR(
      ParseInput(head + "[[point]]\nfeature = \"centre\"\nworld_mm = [0, 0]\npixel = [1, 2]\n"),
      "in.toml:4: both feature and world_mm in [[point]] 1; expected exactly one: a field "
      "feature name or coordinates");
  EXPECT_INPUT_ERROR(ParseInput(head + "[[line]]\nfeature = \"halfway\"\npixels = [[1, 2], [3]]\n"),
                     "in.toml:5: element 2 of pixels in [[line]] 1 is malformed; expected an "
                     "array of [u, v] pixel pairs");
  EXPECT_INPUT_ERROR(ParseInput("image_size_px = [780, 580]\n[[line]]\nfeature = \"halfway\"\n"
                                "pixels = [[1, 2]]\n"),
                     "in.toml:3: feature in [[line]] 1 names a field feature but the file sets no "
                     "field; expected field = \"<field file>\" at the top");
  EXPECT_INPUT_ERROR(ParseInput("image_size_px = [780.5, 580]\n"),
                     "in.toml:1: image_size_px is not two integers from 1 to 65535; expected "
                     "[width, height] in pixels");
  EXPECT_INPUT_ERROR(ParseInput(head + "[fit]\nfix = [\"skew\"]\n"),
                     "in.toml:4: fix in [fit] holds an unknown parameter; expected any of: "
                     "\"focal\", \"aspect\", \"principal_point\", \"k1\" or \"k2\"");
}

}  // namespace
}  // namespace patlab::formats

// Colour class names in thresholds files, CMVision's colors.txt and labels files resolve through
// the colour vocabulary (core/colour_names.h): wordings of one colour are that colour, names close
// to a colour are errors with a did-you-mean, other names are kept as written.
#include "patlab/formats/thresholds_file.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/formats/labels_file.h"

namespace patlab::formats {
namespace {

TEST(ThresholdsFile, TomlClassNamesResolveThroughTheVocabulary) {
  const vision::Thresholds t = ParseThresholdsToml(
      "[[class]]\nname = \"Light Blue\"\n[[class]]\nname = \"magenta\"\n[[class]]\n"
      "name = \"field lines\"\n[[class]]\nname = \"carpet_green\"\n",
      "t.toml");
  ASSERT_EQ(t.classes.size(), 4u);
  EXPECT_EQ(t.classes[0].name, "light-blue");
  EXPECT_EQ(t.classes[1].name, "pink");
  EXPECT_EQ(t.classes[2].name, "field lines");  // no colour, close to none: kept
  EXPECT_EQ(t.classes[3].name, "carpet");
  EXPECT_INPUT_ERROR(ParseThresholdsToml("[[class]]\nname = \"pink\"\n[[class]]\nname = "
                                         "\"Magenta\"\n",
                                         "t.toml"),
                     "t.toml:4: duplicate class name \"pink\"; expected unique names");
  EXPECT_INPUT_ERROR(ParseThresholdsToml("[[class]]\nname = \"geen\"\n", "t.toml"),
                     "t.toml:2: unknown colour 'geen'; expected a colour of settings/colours.toml "
                     "(did you mean 'green'?)");
}

TEST(ThresholdsFile, CmvisionClassNamesResolveThroughTheVocabulary) {
  const vision::Thresholds t = ParseCmvisionColors(
      "[Colors]\n(255,0,255) 0.5 1 Magenta\n(0,0,255) 0.5 1 Dark_Blue\n(255,128,0) 0.5 1 Ball\n"
      "[Thresholds]\n(0:255,0:255,0:255)\n(0:255,0:255,0:255)\n(0:255,0:255,0:255)\n",
      "colors.txt");
  EXPECT_EQ(t.classes[0].name, "pink");
  EXPECT_EQ(t.classes[1].name, "dark-blue");
  EXPECT_EQ(t.classes[2].name, "Ball");
  EXPECT_INPUT_ERROR(ParseCmvisionColors("[Colors]\n(255,0,255) 0.5 1 pink\n(255,0,255) 0.5 1 "
                                         "Fuchsia\n[Thresholds]\n(0:255,0:255,0:255)\n"
                                         "(0:255,0:255,0:255)\n",
                                         "colors.txt"),
                     "colors.txt:3: colour 'pink' listed twice (names that differ only in case, "
                     "spaces, hyphens or underscores, or are aliases, are one colour); expected "
                     "distinct colours");
  EXPECT_INPUT_ERROR(ParseCmvisionColors("[Colors]\n(255,0,255) 0.5 1 Yelow\n[Thresholds]\n"
                                         "(0:255,0:255,0:255)\n",
                                         "colors.txt"),
                     "colors.txt:2: unknown colour 'Yelow'; expected a colour of "
                     "settings/colours.toml (did you mean 'yellow'?)");
}

// CMVision's merge is a density in [0, 1] and expected_num a count; NaN, infinity, values
// outside the range and overflowing integers are refused at their line (TOML: file:line and key).
TEST(ThresholdsFile, MergeDensitiesAndExpectedCountsAreBounded) {
  const auto cmvision = [](const std::string& colour) {
    return ParseCmvisionColors("[Colors]\n" + colour + "\n[Thresholds]\n(0:255,0:255,0:255)\n",
                               "colors.txt");
  };
  EXPECT_EQ(cmvision("(255,0,255) 1 0 pink").classes[0].merge, 1.0);
  EXPECT_EQ(cmvision("(255,0,255) 0 1000000 pink").classes[0].expected_num, 1000000);
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) nan 1 pink"),
                     "colors.txt:2: merge is nan; expected a density in [0, 1]");
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) inf 1 pink"),
                     "colors.txt:2: merge is inf; expected a density in [0, 1]");
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) 1.5 1 pink"),
                     "colors.txt:2: merge is 1.5; expected a density in [0, 1]");
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) -0.1 1 pink"),
                     "colors.txt:2: merge is -0.1; expected a density in [0, 1]");
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) 0.5 1000001 pink"),
                     "colors.txt:2: expected_num is 1000001; expected an integer in [0, 1000000]");
  EXPECT_INPUT_ERROR(cmvision("(255,0,255) 0.5 99999999999999999999999 pink"),
                     "colors.txt:2: expected_num is 9223372036854775807; expected an integer in "
                     "[0, 1000000]");
  EXPECT_INPUT_ERROR(ParseThresholdsToml("[[class]]\nname = \"pink\"\nmerge = nan\n", "t.toml"),
                     "t.toml:3: merge in [[class]] 1 is nan; expected a finite number");
  EXPECT_INPUT_ERROR(ParseThresholdsToml("[[class]]\nname = \"pink\"\nmerge = 2.0\n", "t.toml"),
                     "t.toml:3: merge in [[class]] 1 is 2; expected a density in [0, 1]");
  EXPECT_INPUT_ERROR(
      ParseThresholdsToml("[[class]]\nname = \"pink\"\nexpected_num = -1\n", "t.toml"),
      "t.toml:3: expected_num in [[class]] 1 is -1; expected an integer in [0, 1000000]");
  EXPECT_INPUT_ERROR(
      ParseThresholdsToml("[[class]]\nname = \"pink\"\nmin_area_px = 4294967296\n", "t.toml"),
      "t.toml:3: min_area_px 4294967296 in [[class]] 1; expected 0..268435456 pixels");
}

TEST(LabelsFile, ClassNamesResolveThroughTheVocabulary) {
  const vision::Labels l = ParseLabels(
      "image = \"f.png\"\n[[class]]\nname = \"Sky Blue\"\npoints = [[1, 1]]\n[[class]]\n"
      "name = \"violet\"\npoints = [[2, 2]]\n",
      "l.toml", ".");
  EXPECT_EQ(l.classes[0].name, "light-blue");
  EXPECT_EQ(l.classes[1].name, "purple");
  EXPECT_INPUT_ERROR(ParseLabels("image = \"f.png\"\n[[class]]\nname = \"purpel\"\npoints = "
                                 "[[1, 1]]\n",
                                 "l.toml", "."),
                     "l.toml:3: unknown colour 'purpel'; expected a colour of "
                     "settings/colours.toml (did you mean 'purple'?)");
}

}  // namespace
}  // namespace patlab::formats

#include "patlab/detect/settings.h"

#include <gtest/gtest.h>

#include <limits>

#include "../expect_error.h"
#include "patlab/core/error.h"
#include "patlab/formats/detector_settings.h"

namespace patlab::formats {
namespace {

const std::string kExperiments = std::string(PATLAB_SOURCE_DIR) + "/experiments";

TEST(Settings, ShippedFileLoadsWithDocumentedDefaults) {
  const detect::DetectorConfig config = LoadDetectorSettings(kExperiments + "/detector.toml");
  const detect::DetectorOptions defaults;
  EXPECT_EQ(config.palette.size(), 8u);
  EXPECT_EQ(config.options.patch_sigma_mm, defaults.patch_sigma_mm);
  EXPECT_EQ(config.options.geometry_confidence, defaults.geometry_confidence);
  EXPECT_EQ(config.options.reach_margin_mm, defaults.reach_margin_mm);
  EXPECT_EQ(config.options.area_ratio_min, defaults.area_ratio_min);
  EXPECT_EQ(config.options.area_ratio_max, defaults.area_ratio_max);
  EXPECT_EQ(config.options.missing_patch, defaults.missing_patch);
  EXPECT_EQ(config.options.max_neighbours, defaults.max_neighbours);
  EXPECT_EQ(config.options.estimator, defaults.estimator);
  EXPECT_EQ(config.options.ml.max_iterations, defaults.ml.max_iterations);
  ASSERT_EQ(config.patterns.size(), 1u);
  EXPECT_EQ(config.patterns[0].pattern.name, "ssl-standard");
  EXPECT_EQ(config.patterns[0].codebook.entries.size(), 16u);
}

TEST(Settings, MinimalFileGeneratesTheCodebook) {
  const detect::DetectorConfig config = ParseDetectorSettings(
      "palette = [\"blue\", \"pink\", \"green\", \"cyan\"]\n"
      "[detector]\nmissing_patch = \"fit\"\nestimator = \"ml\"\n"
      "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"pink\", \"green\", \"cyan\"]\n"
      "key_colours = [\"blue\"]\n",
      "s.toml", kExperiments);
  EXPECT_EQ(config.options.missing_patch, detect::MissingPatchPolicy::kFit);
  EXPECT_EQ(config.options.estimator, estimate::Estimator::kMl);
  EXPECT_EQ(config.patterns[0].codebook.entries.size(), 8u);
}

void ExpectSettingsError(const std::string& text, const std::string& message) {
  EXPECT_INPUT_ERROR(ParseDetectorSettings(text, "bad.toml", kExperiments), message);
}

const std::string kPaletteLine =
    "palette = [\"blue\", \"yellow\", \"pink\", \"green\"]\n";  // line 1
const std::string kPattern =
    "[[pattern]]\npattern = \"ssl-standard\"\nid_colours = [\"pink\", \"green\"]\n"
    "key_colours = [\"blue\"]\n";

TEST(Settings, BadFilesGiveTheirMessages) {
  ExpectSettingsError(kPaletteLine + "[detector]\npatch_sigma_mm = -1\n" + kPattern,
                      "bad.toml:3: patch_sigma_mm is -1; expected a finite number > 0 (mm)");
  ExpectSettingsError(kPaletteLine + "[detector]\narea_ratio_min = 3\n" + kPattern,
                      "bad.toml:2: area_ratio_max is 2.5; expected a finite number > "
                      "area_ratio_min (3)");
  ExpectSettingsError(kPaletteLine + "[detector]\npatch_sigma = 1\n" + kPattern,
                      "bad.toml:3: unknown key 'patch_sigma' in [detector]; expected one of: "
                      "patch_sigma_mm, geometry_confidence, reach_margin_mm, area_ratio_min, "
                      "area_ratio_max, missing_patch, max_neighbours, estimator, "
                      "ml_max_iterations");
  ExpectSettingsError(kPaletteLine + "[detector]\nmissing_patch = \"guess\"\n" + kPattern,
                      "bad.toml:3: missing_patch is \"guess\"; expected \"reject\" or \"fit\"");
  ExpectSettingsError(kPaletteLine + "[detector]\nestimator = \"best\"\n" + kPattern,
                      "bad.toml:3: estimator is \"best\"; expected \"fast\", \"ml\", \"lsq\" or "
                      "\"key\"");
  ExpectSettingsError(kPaletteLine + "[detector]\nmax_neighbours = 2.5\n" + kPattern,
                      "bad.toml:3: max_neighbours in [detector] is a float; expected an integer");
  // One limit for ml_max_iterations (estimate::Check), at the key's line.
  ExpectSettingsError(kPaletteLine + "[detector]\nml_max_iterations = 0\n" + kPattern,
                      "bad.toml:3: ml_max_iterations is 0; expected an integer in [1, 1000]");
  ExpectSettingsError(kPaletteLine + "[detector]\nml_max_iterations = 5000000\n" + kPattern,
                      "bad.toml:3: ml_max_iterations is 5000000; expected an integer in [1, 1000]");
  ExpectSettingsError(kPaletteLine + "[detector]\nmax_neighbours = 17\n" + kPattern,
                      "bad.toml:3: max_neighbours is 17; expected an integer in [1, 16]");
  ExpectSettingsError(kPaletteLine + "[detector]\nmax_neighbours = 3\n" + kPattern,
                      "bad.toml: pattern ssl-standard: max_neighbours is 3; expected at least 4 "
                      "(its non-key patches)");
  ExpectSettingsError(kPaletteLine,
                      "bad.toml:1: no patterns; expected at least one [[pattern]] table");
  ExpectSettingsError("palette = []\n" + kPattern,
                      "bad.toml:1: palette is an empty array; expected a non-empty array of "
                      "colour names");
  ExpectSettingsError(kPaletteLine +
                          "[[pattern]]\npattern = \"ssl-standard\"\nid_colours = [\"pink\"]\n"
                          "key_colours = [\"blue\", \"purple\"]\n",
                      "bad.toml:5: colour \"purple\" is not in the palette; expected one of: "
                      "blue, yellow, pink, green");
  ExpectSettingsError(
      kPaletteLine + "[[pattern]]\npattern = \"ssl-standard\"\nkey_colours = [\"blue\"]\n",
      "bad.toml:3: [[pattern]] 0 has neither codebook nor id_colours; expected "
      "exactly one of them");
  ExpectSettingsError(kPaletteLine +
                          "[[pattern]]\npattern = \"hexagon\"\nid_colours = [\"pink\"]\n"
                          "key_colours = [\"blue\"]\n",
                      "bad.toml:3: pattern 'hexagon' not found; expected a pattern file path or a "
                      "name in " +
                          std::string(PATLAB_SOURCE_DIR) + "/patterns/");
  ExpectSettingsError(kPaletteLine +
                          "[[pattern]]\npattern = \"linear\"\nid_colours = [\"pink\"]\n"
                          "key_colours = [\"blue\"]\nsymmetry_tolerance_mm = -2\n",
                      "bad.toml:6: symmetry_tolerance_mm is -2; expected a number >= 0 (mm)");
  ExpectSettingsError(kPaletteLine + "[detector\n",
                      "bad.toml:2: TOML syntax error: Error while parsing table header: expected "
                      "']', saw '\\n'");
}

// The [frame] table: read for the camera front ends, checked by every loader, never part of the
// detector's own options.
TEST(Settings, FrameTableIsReadAndCheckedButLeavesTheDetectorOptions) {
  const std::string text = kPaletteLine + "[detector]\nmissing_patch = \"reject\"\n" +
                           "[frame]\nedge_loss_px = 0.5\nmissing_patch = \"fit\"\nlight_luma = "
                           "76\nbinning = 3\n" +
                           kPattern;
  const detect::FrameSettings frame = ParseFrameSettings(text, "s.toml");
  ASSERT_TRUE(frame.edge_loss_px.has_value());
  EXPECT_EQ(*frame.edge_loss_px, 0.5);
  ASSERT_TRUE(frame.missing_patch.has_value());
  EXPECT_EQ(*frame.missing_patch, detect::MissingPatchPolicy::kFit);
  ASSERT_TRUE(frame.light_luma.has_value());
  EXPECT_EQ(*frame.light_luma, 76.0);
  EXPECT_EQ(frame.binning, 3);
  EXPECT_EQ(ParseDetectorSettings(text, "s.toml", kExperiments).options.missing_patch,
            detect::MissingPatchPolicy::kReject);
  const detect::FrameSettings none = ParseFrameSettings(kPaletteLine + kPattern, "s.toml");
  EXPECT_FALSE(none.edge_loss_px.has_value());
  EXPECT_FALSE(none.missing_patch.has_value());
  EXPECT_FALSE(none.light_luma.has_value());
  EXPECT_FALSE(none.binning.has_value());
  // The shipped file: simulations keep "reject", camera frames fit (docs/detect.md).
  EXPECT_EQ(LoadFrameSettings(kExperiments + "/detector.toml").missing_patch,
            detect::MissingPatchPolicy::kFit);
}

TEST(Settings, BadFrameTablesGiveTheirMessages) {
  const auto frame_error = [](const std::string& table, const std::string& message) {
    const std::string text = kPaletteLine + "[frame]\n" + table + kPattern;
    ExpectSettingsError(text, message);
    EXPECT_INPUT_ERROR(ParseFrameSettings(text, "bad.toml"), message);
  };
  frame_error("edge_loss_px = -1\n",
              "bad.toml:3: edge_loss_px is -1; expected a number in [0, 10] (px)");
  frame_error("edge_loss_px = 10.5\n",
              "bad.toml:3: edge_loss_px is 10.5; expected a number in [0, 10] (px)");
  frame_error("edge_loss_px = nan\n",
              "bad.toml:3: edge_loss_px in [frame] is nan; expected a finite number");
  frame_error("missing_patch = \"sometimes\"\n",
              "bad.toml:3: missing_patch is \"sometimes\"; expected \"reject\" or \"fit\"");
  frame_error("edge_loss = 1\n",
              "bad.toml:3: unknown key 'edge_loss' in [frame]; expected one of: edge_loss_px, "
              "missing_patch, light_luma, binning");
  frame_error("light_luma = 0\n", "bad.toml:3: light_luma is 0; expected in (0, 255]");
  frame_error("binning = 0\n", "bad.toml:3: binning is 0; expected an integer in [1, 8]");
  frame_error("binning = 9\n", "bad.toml:3: binning is 9; expected an integer in [1, 8]");
  frame_error("binning = 2.5\n", "bad.toml:3: binning in [frame] is a float; expected an integer");
  frame_error("light_luma = 300\n", "bad.toml:3: light_luma is 300; expected in (0, 255]");
  ExpectSettingsError(kPaletteLine + "frame = 1\n" + kPattern,
                      "bad.toml:2: frame is an integer; expected a table");
  detect::FrameSettings ok;
  ok.edge_loss_px = 0.0;
  EXPECT_TRUE(detect::Check(ok).empty());
  ok.edge_loss_px = std::numeric_limits<double>::infinity();
  ASSERT_EQ(detect::Check(ok).size(), 1u);
  EXPECT_EQ(detect::Check(ok)[0].message, "edge_loss_px is inf; expected a number in [0, 10] (px)");
}

}  // namespace
}  // namespace patlab::formats

namespace patlab::formats {
namespace {

TEST(Settings, PaperPatternsFileLoadsWithTableTwoCounts) {
  const detect::DetectorConfig config = LoadDetectorSettings(kExperiments + "/detector-paper.toml");
  ASSERT_EQ(config.patterns.size(), 4u);
  const size_t expected[4] = {4, 6, 20, 256};  // Table II, 4 colours (our counting rule)
  for (int p = 0; p < 4; ++p) EXPECT_EQ(config.patterns[p].codebook.entries.size(), expected[p]);
}

}  // namespace
}  // namespace patlab::formats

namespace patlab::formats {
namespace {

// Colour names that differ only in wording are one colour (core/colour_names.h): the palette,
// the key and the ID colours are read as the vocabulary's canonical names.
TEST(Settings, ColourNamesInAnyWordingAreTheVocabularysNames) {
  const detect::DetectorConfig config = ParseDetectorSettings(
      "palette = [\"Blue\", \"MAGENTA\", \"Light Green\", \"dark_blue\"]\n"
      "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"magenta\", \"Light_Green\", "
      "\"BLUE\"]\nkey_colours = [\"darkblue\"]\n",
      "s.toml", kExperiments);
  EXPECT_EQ(config.palette, (std::vector<std::string>{"blue", "pink", "light-green", "dark-blue"}));
  EXPECT_EQ(config.patterns[0].key_colours, (std::vector<std::string>{"dark-blue"}));
  EXPECT_EQ(config.patterns[0].codebook.colours,
            (std::vector<std::string>{"pink", "light-green", "blue"}));
}

TEST(Settings, UnknownColourNamesAreErrorsWithADidYouMean) {
  ExpectSettingsError("palette = [\"blue\", \"yelow\"]\n" + kPattern,
                      "bad.toml:1: unknown colour 'yelow'; expected a colour of "
                      "settings/colours.toml (did you mean 'yellow'?)");
  // Two wordings of one colour are that colour twice.
  ExpectSettingsError(
      "palette = [\"pink\", \"Magenta\"]\n" + kPattern,
      "bad.toml:1: palette lists \"Magenta\" twice; expected distinct colour names");
}

}  // namespace
}  // namespace patlab::formats

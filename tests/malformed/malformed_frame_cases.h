// More cases of tests/malformed/malformed_test.cpp, in the form malformed_case.h declares
// declares them: the settings file's [frame] table and patlab detect --edge-loss-px
// (docs/detect.md, "The segmentation's edge loss").
#pragma once

#include <string>
#include <vector>

#include "malformed_case.h"

namespace patlab::testing {

// A patlab detect run on the golden frame with a settings file whose [frame] table holds
// `frame_line` (its line 5), plus `extra` arguments; all that differs between the cases.
inline MalformedCase FrameSettingsCase(const char* name, const std::string& frame_line,
                                       const std::string& extra, const std::string& message) {
  using namespace std::string_literals;
  return {name,
          {{"s.toml",
            "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\n"
            "patch_sigma_mm = 2.0\n[frame]\n"s +
                frame_line +
                "\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = "
                "\"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"},
           {"c.toml",
            "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = "
            "[\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", "
            "\"pink\", \"green\", \"pink\"]\n"s}},
          "detect {src}/tests/data/golden/ssl-frame.png -t "
          "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
          "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
          "{dir}out/d.csv"s +
              extra,
          2,
          message,
          nullptr};
}

inline const std::vector<MalformedCase>& FrameSettingsMalformedCases() {
  static const std::vector<MalformedCase> cases = {
      FrameSettingsCase(
          "SettingsFrameEdgeLossNegative", "edge_loss_px = -1", "",
          "patlab detect: {dir}s.toml:5: edge_loss_px is -1; expected a number in [0, 10] (px)"),
      FrameSettingsCase("SettingsFrameMissingPatchPolicy", "missing_patch = \"always\"", "",
                        "patlab detect: {dir}s.toml:5: missing_patch is \"always\"; expected "
                        "\"reject\" or \"fit\""),
      FrameSettingsCase(
          "SettingsFrameUnknownKey", "edge_loss = 1", "",
          "patlab detect: {dir}s.toml:5: unknown key 'edge_loss' in [frame]; expected "
          "one of: edge_loss_px, missing_patch, light_luma, binning"),
      FrameSettingsCase(
          "SettingsFrameBinningTooLarge", "binning = 12", "",
          "patlab detect: {dir}s.toml:5: binning is 12; expected an integer in [1, 8]"),
      FrameSettingsCase("DetectEdgeLossFlagTooLarge", "edge_loss_px = 1", " --edge-loss-px 12",
                        "patlab detect: --edge-loss-px is 12; expected a number in [0, 10] (px)"),
  };
  return cases;
}

}  // namespace patlab::testing

// More cases of tests/malformed/malformed_test.cpp, as MalformedCases() (malformed_cases.h)
// declares them: the settings file's [frame] table and patlab detect --edge-loss-px
// (docs/detect.md, "The segmentation's edge loss").
#pragma once

#include <string>
#include <vector>

#include "malformed_cases.h"

namespace patlab::testing {

inline const std::vector<MalformedCase>& FrameSettingsMalformedCases() {
  using namespace std::string_literals;
  static const std::vector<MalformedCase> cases = {
      {"SettingsFrameEdgeLossNegative",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\n[frame]\nedge_loss_px = -1\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:5: edge_loss_px is -1; expected a number in [0, 10] (px)"s,
       nullptr},
      {"SettingsFrameMissingPatchPolicy",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\n[frame]\nmissing_patch = \"always\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:5: missing_patch is \"always\"; expected \"reject\" or \"fit\""s,
       nullptr},
      {"SettingsFrameUnknownKey",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\n[frame]\nedge_loss = 1\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:5: unknown key 'edge_loss' in [frame]; expected one of: edge_loss_px, missing_patch"s,
       nullptr},
      {"DetectEdgeLossFlagTooLarge",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\n[frame]\nedge_loss_px = 1\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv --edge-loss-px 12",
       2,
       "patlab detect: --edge-loss-px is 12; expected a number in [0, 10] (px)"s,
       nullptr},
  };
  return cases;
}

}  // namespace patlab::testing

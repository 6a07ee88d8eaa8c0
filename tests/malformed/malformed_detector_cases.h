// Cases of the malformed-input suite (malformed_cases.h): the detector's inputs: settings,
// thresholds, colors.txt and camera calibrations.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "malformed_case.h"

namespace patlab::testing {

inline std::vector<MalformedCase> DetectorInputMalformedCases() {
  namespace fs = std::filesystem;
  using namespace std::string_literals;
  return {
      {"SettingsPatchSigmaZero",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 0\nestimator = \"fast\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:3: patch_sigma_mm is 0; expected a finite number > 0 (mm)"s,
       nullptr},
      {"SettingsMlIterationsHuge",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nestimator = \"ml\"\nml_max_iterations = 2000000000\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:5: ml_max_iterations is 2000000000; expected an integer in [1, 1000]"s,
       nullptr},
      {"SettingsMaxNeighboursZero",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nmax_neighbours = 0\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:4: max_neighbours is 0; expected an integer in [1, 16]"s,
       nullptr},
      {"SettingsMaxNeighboursBelowPatches",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nmax_neighbours = 2\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml: pattern ssl-standard: max_neighbours is 2; expected at least 4 (its non-key patches)"s,
       nullptr},
      {"SettingsEstimatorUnknown",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nestimator = \"fastest\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:4: estimator is \"fastest\"; expected \"fast\", \"ml\", \"lsq\" or \"key\""s,
       nullptr},
      {"SettingsMissingPatchPolicy",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nmissing_patch = \"maybe\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:4: missing_patch is \"maybe\"; expected \"reject\" or \"fit\""s,
       nullptr},
      {"SettingsKeyColourNotInPalette",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nestimator = \"fast\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"red\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:8: colour \"red\" is not in the palette; expected one of: blue, yellow, pink, green, orange"s,
       nullptr},
      {"SettingsUnknownKey",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nestimatr = \"fast\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:4: unknown key 'estimatr' in [detector]; expected one of: patch_sigma_mm, geometry_confidence, reach_margin_mm, area_ratio_min, area_ratio_max, missing_patch, max_neighbours, estimator, ml_max_iterations"s,
       nullptr},
      {"SettingsPaletteNotArray",
       {{"s.toml",
         "palette = \"blue\"\n[detector]\npatch_sigma_mm = 2.0\nestimator = \"fast\"\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:1: palette is a string; expected a non-empty array of colour names"s,
       nullptr},
      {"SettingsPatternFileMissing",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\nestimator = \"fast\"\n[[pattern]]\npattern = \"nothere.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}nothere.toml: cannot open file; expected a readable TOML file"s,
       nullptr},
      {"SettingsGeometryConfidenceOne",
       {{"s.toml",
         "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n[detector]\npatch_sigma_mm = 2.0\ngeometry_confidence = 1.0\n[[pattern]]\npattern = \"{src}/patterns/ssl-standard.toml\"\ncodebook = \"c.toml\"\nkey_colours = [\"blue\", \"yellow\"]\n"s},
        {"c.toml",
         "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\nslots = [\"pink\", \"pink\", \"green\", \"pink\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\", \"green\", \"pink\"]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml:4: geometry_confidence is 1; expected a probability in (0, 1)"s,
       nullptr},
      {"SettingsIsDirectory",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s {dir}s.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}s.toml: is a directory; expected a TOML file"s,
       [](const std::string& dir) { fs::create_directory(dir + "s.toml"); }},
      {"ThresholdsSpaceUnknown",
       {{"t.toml",
         "space = \"hsv\"\n[[class]]\nname = \"blue\"\ndisplay = [35, 75, 210]\nr = [20, 50]\ng = [60, 90]\nb = [195, 225]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml:1: space is \"hsv\"; expected \"yuv\" or \"rgb\""s,
       nullptr},
      {"ThresholdsRangeInverted",
       {{"t.toml",
         "space = \"rgb\"\n[[class]]\nname = \"blue\"\ndisplay = [35, 75, 210]\nr = [50, 20]\ng = [60, 90]\nb = [195, 225]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml:5: empty R range 50:20; expected lo <= hi"s,
       nullptr},
      {"ThresholdsRangeBeyond255",
       {{"t.toml",
         "space = \"rgb\"\n[[class]]\nname = \"blue\"\ndisplay = [35, 75, 210]\nr = [20, 300]\ng = [60, 90]\nb = [195, 225]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml:5: R bound 300 out of range; expected 0..255"s,
       nullptr},
      {"ThresholdsNoClass",
       {{"t.toml", "space = \"rgb\"\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml: no colour classes; expected at least one [[class]] table"s,
       nullptr},
      {"ThresholdsUnknownKey",
       {{"t.toml",
         "space = \"rgb\"\n[[class]]\nname = \"blue\"\ndisplya = [35, 75, 210]\nr = [20, 50]\ng = [60, 90]\nb = [195, 225]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml:4: unknown key 'displya' in [[class]] 1; expected one of: name, display, r, g, b, min_area_px, max_area_px, merge, expected_num"s,
       nullptr},
      {"ThresholdsDisplayMalformed",
       {{"t.toml",
         "space = \"rgb\"\n[[class]]\nname = \"blue\"\ndisplay = [35, 75]\nr = [20, 50]\ng = [60, 90]\nb = [195, 225]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml:4: display in [[class]] 1 is not [R, G, B]; expected three integers in 0..255"s,
       nullptr},
      {"ThresholdsIsDirectory",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}t.toml: is a directory; expected a thresholds file"s,
       [](const std::string& dir) { fs::create_directory(dir + "t.toml"); }},
      {"ColorsTxtNoThresholds",
       {{"colors.txt", "[Colors]\n(255,128,  0) 0.5000 1 orange\n(  0,  0,255) 0.6000 5 blue\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt: 2 colours but 0 thresholds; expected one [Thresholds] line per [Colors] line"s,
       nullptr},
      {"ColorsTxtBadColourLine",
       {{"colors.txt",
         "[Colors]\n(255,128) 0.5 1 orange\n(  0,  0,255) 0.6000 5 blue\n[Thresholds]\n( 60:160, 60:115,160:200)\n(100:255,  0: 95,135:175)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt:2: bad [Colors] line '(255,128) 0.5 1 orange'; expected (R,G,B) merge expected_num Name"s,
       nullptr},
      {"ColorsTxtThresholdBeyond255",
       {{"colors.txt",
         "[Colors]\n(255,128,  0) 0.5000 1 orange\n(  0,  0,255) 0.6000 5 blue\n[Thresholds]\n( 60:300, 60:115,160:200)\n(100:255,  0: 95,135:175)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt:5: Y bound 300 out of range; expected 0..255"s,
       nullptr},
      {"ColorsTxtMoreThresholdsThanColours",
       {{"colors.txt",
         "[Colors]\n(255,128,  0) 0.5000 1 orange\n(  0,  0,255) 0.6000 5 blue\n[Thresholds]\n( 60:160, 60:115,160:200)\n(100:255,  0: 95,135:175)\n( 1:2, 3:4, 5:6)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt:7: threshold 3 but only 2 colours; expected one [Thresholds] line per [Colors] line"s,
       nullptr},
      {"ColorsTxtEmpty",
       {{"colors.txt", ""s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt: no colour classes; expected at least one [[class]] table"s,
       nullptr},
      {"ColorsTxtLongLine",
       {{"colors.txt",
         "[Colors]\n(99999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999)\n(  0,  0,255) 0.6000 5 blue\n[Thresholds]\n( 60:160, 60:115,160:200)\n(100:255,  0: 95,135:175)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}colors.txt:2: bad [Colors] line '(99999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999... (5002 bytes)'; expected (R,G,B) merge expected_num Name"s,
       nullptr},
      {"CalibrationCameraBelowFloor",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, -500]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:8: the camera centre is at height -500 mm; expected a camera above the floor, at a height in (0, 100000] mm"s,
       nullptr},
      {"CalibrationCameraTooHigh",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, 1e9]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:8: the camera centre is at height 1000000000 mm; expected a camera above the floor, at a height in (0, 100000] mm"s,
       nullptr},
      {"CalibrationDistortionHuge",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\nk1 = 1e6\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:8: pinhole.k1 is 1000000; expected a number in [-10, 10]"s,
       nullptr},
      {"CalibrationFocalZero",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:4: fx_px in [pinhole] is 0; expected > 0"s,
       nullptr},
      {"CalibrationModelUnknown",
       {{"c.toml",
         "model = \"fisheye\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:1: model is \"fisheye\"; expected \"pinhole\" or \"homography\""s,
       nullptr},
      {"CalibrationNoPinholeTable",
       {{"c.toml", "model = \"pinhole\"\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:1: model = \"pinhole\" needs a [pinhole] table; expected fx_px, fy_px, cx_px, cy_px and extrinsics"s,
       nullptr},
      {"CalibrationHomographySingular",
       {{"c.toml",
         "model = \"homography\"\n[[homography]]\nheight_mm = 0\nmatrix = [[1, 0, 0], [0, 0, 0], [0, 0, 1]]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:4: matrix in [[homography]] 1 is singular; expected an invertible homography"s,
       nullptr},
      {"CalibrationImageSizeNegative",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [-640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:2: image_size_px is not two integers in [1, 100000]; expected [width, height] in pixels"s,
       nullptr},
      {"CalibrationBothExtrinsics",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_px = 800.0\ncx_px = 319.5\ncy_px = 239.5\ntranslation_mm = [0, 0, 4000]\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:9: [pinhole] needs exactly one form of extrinsics; expected rotation_rodrigues and translation_mm, or camera_position_mm and yaw_deg"s,
       nullptr},
      {"CalibrationUnknownKey",
       {{"c.toml",
         "model = \"pinhole\"\nimage_size_px = [640, 480]\n[pinhole]\nfx_px = 800.0\nfy_pix = 800.0\ncx_px = 319.5\ncy_px = 239.5\ncamera_position_mm = [0, 0, 4000]\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:5: unknown key 'fy_pix' in [pinhole]; expected one of: fx_px, fy_px, cx_px, cy_px, k1, k2, rotation_rodrigues, translation_mm, camera_position_mm, yaw_deg"s,
       nullptr},
      {"CalibrationResidualNegative",
       {{"c.toml",
         "model = \"homography\"\nimage_size_px = [640, 480]\n[[homography]]\nheight_mm = 140\nmatrix = [[1, 0, 0], [0, -1, 800], [0, 0, 1]]\n[heights]\ndefault_mm = 140\n[[residual]]\nheight_mm = 140\nrms_mm = -3\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c {dir}c.toml --out "
       "{dir}out/d.csv",
       2,
       "patlab detect: {dir}c.toml:10: rms_mm is -3 in [[residual]] 1; expected a residual >= 0 (mm)"s,
       nullptr},
  };
}

}  // namespace patlab::testing

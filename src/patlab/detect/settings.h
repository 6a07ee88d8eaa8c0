// Detector settings files (format and defaults: experiments/detector.toml).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/detect/detector.h"

namespace patlab::detect {

// Reads a detector settings file: palette, [detector] options, and one [[pattern]] table per
// enabled pattern (pattern file, codebook file or ID colours, team key colours, symmetry
// tolerance). Relative paths are relative to the settings file's folder. Throws InputError
// "file:line: what is wrong; expected what" for the first problem, including a broken option
// constraint (Check(const DetectorOptions&)) at the line of that option.
DetectorConfig LoadDetectorSettings(const std::string& path);
// The same from text; `source_name` stands for the file in messages and `base_dir` resolves
// relative paths.
DetectorConfig ParseDetectorSettings(const std::string& text, const std::string& source_name,
                                     const std::string& base_dir);

// The same from values, for callers that build a configuration in code (patlab evaluate); the
// settings files go through these too. MakeDetectorPattern is one [[pattern]] table: the
// pattern's symmetry at symmetry_tolerance_mm, then its codebook read from `codebook_file` (when
// not empty) or generated from `id_colours` (every ID, GenerateCodebook). MakeDetectorConfig
// checks the whole configuration as the Detector does (palette, options, colours in the
// palette). Both throw InputError.
DetectorPattern MakeDetectorPattern(Pattern pattern, std::vector<std::string> key_colours,
                                    const std::string& codebook_file,
                                    const std::vector<std::string>& id_colours,
                                    double symmetry_tolerance_mm = 10.0);
DetectorConfig MakeDetectorConfig(std::vector<std::string> palette, const DetectorOptions& options,
                                  std::vector<DetectorPattern> patterns);

// The optional [frame] table of a settings file: how a camera front end (vision::FrameDetector,
// patlab detect) adapts the detector to real frames. The Detector never reads it, so detection on
// simulated blobs (simulate, evaluate, compare, scenes) is the same with or without it. An unset
// field leaves the front end's own default (vision::FrameDetectorOptions, ApplyFrameSettings).
struct FrameSettings {
  // Pixels a segmented region loses all around its patch, in [0, kMaxEdgeLossPx]
  // (vision::FrameDetectorOptions::edge_loss_px; default there 1 px).
  std::optional<double> edge_loss_px;
  // The missing-patch policy on camera frames, replacing [detector] missing_patch there: a real
  // frame regularly loses one patch of a pattern (occlusion, a sector merged with the robot's
  // body, a colour the light does not show) where simulated blobs lose none unless asked to.
  std::optional<MissingPatchPolicy> missing_patch;
};
inline constexpr double kMaxEdgeLossPx = 10.0;

// Every broken constraint (core/options.h): edge_loss_px, when set, finite and in
// [0, kMaxEdgeLossPx].
std::vector<OptionsProblem> Check(const FrameSettings& settings);
// The [frame] table of a settings file (all fields unset without one). Throws InputError
// "file:line: ...; expected ..." for an unknown key or a bad value. ParseDetectorSettings checks
// the table the same way, so a settings file with a broken [frame] is rejected everywhere.
FrameSettings LoadFrameSettings(const std::string& path);
FrameSettings ParseFrameSettings(const std::string& text, const std::string& source_name);

}  // namespace patlab::detect

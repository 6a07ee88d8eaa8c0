// Detector settings files (format and defaults: experiments/detector.toml): the palette, the
// [detector] options, the [frame] table of camera front ends and one [[pattern]] table per
// pattern, read into the detection core's values (detect/settings.h, detect/detector.h).
#pragma once

#include <string>
#include <vector>

#include "patlab/core/pattern.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"

namespace patlab::formats {

// Reads a detector settings file: palette, [detector] options, and one [[pattern]] table per
// enabled pattern (pattern file, codebook file or ID colours, team key colours, symmetry
// tolerance). Relative paths are relative to the settings file's folder. Throws InputError
// "file:line: what is wrong; expected what" for the first problem, including a broken option
// constraint (Check(const DetectorOptions&)) at the line of that option.
detect::DetectorConfig LoadDetectorSettings(const std::string& path);
// The same from text; `source_name` stands for the file in messages and `base_dir` resolves
// relative paths.
detect::DetectorConfig ParseDetectorSettings(const std::string& text,
                                             const std::string& source_name,
                                             const std::string& base_dir);

// One [[pattern]] table from values (patlab evaluate and compare, scene files; the settings
// files go through it too): the pattern's symmetry at symmetry_tolerance_mm, then its codebook
// read from `codebook_file` (when not empty; formats/codebook_file.h) or generated from
// `id_colours` (every ID, GenerateCodebook). Throws InputError. MakeDetectorConfig
// (detect/settings.h) then checks the whole configuration.
detect::DetectorPattern MakeDetectorPattern(Pattern pattern, std::vector<std::string> key_colours,
                                            const std::string& codebook_file,
                                            const std::vector<std::string>& id_colours,
                                            double symmetry_tolerance_mm = 10.0);

// The [frame] table of a settings file (all fields unset without one). Throws InputError
// "file:line: ...; expected ..." for an unknown key or a bad value. ParseDetectorSettings checks
// the table the same way, so a settings file with a broken [frame] is rejected everywhere.
detect::FrameSettings LoadFrameSettings(const std::string& path);
detect::FrameSettings ParseFrameSettings(const std::string& text, const std::string& source_name);

}  // namespace patlab::formats

// Detector settings files (format and defaults: experiments/detector.toml).
#pragma once

#include <string>

#include "detect/detector.h"

namespace patlab::detect {

// Reads a detector settings file: palette, [detector] options, and one [[pattern]] table per
// enabled pattern (pattern file, codebook file or ID colours, team key colours, symmetry
// tolerance). Relative paths are relative to the settings file's folder. Throws InputError
// "file:line: what is wrong; expected what" for the first problem, including a broken option
// constraint (ValidateDetectorOptions) at the line of that option.
DetectorConfig LoadDetectorSettings(const std::string& path);
// The same from text; `source_name` stands for the file in messages and `base_dir` resolves
// relative paths.
DetectorConfig ParseDetectorSettings(const std::string& text, const std::string& source_name,
                                     const std::string& base_dir);

}  // namespace patlab::detect

// Detector settings files (format and defaults: experiments/detector.toml).
#pragma once

#include <string>
#include <vector>

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

}  // namespace patlab::detect

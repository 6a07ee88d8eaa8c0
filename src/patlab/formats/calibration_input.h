// Calibration-input files (docs/file-formats.md#calibration-input): what a user measured in one
// frame -- known points, points on field lines and circles, patterns of known layout at known
// heights -- and the fit's options, read into calib/calibrate.h's CalibrationInput.
#pragma once

#include <string>
#include <string_view>

#include "patlab/calib/calibrate.h"

namespace patlab::formats {

// Reads a calibration-input TOML file (docs/file-formats.md#calibration-input). The files it
// names (`field = "..."`, `pattern = "..."`) are read relative to the file's own directory;
// ParseCalibrationInput reads them relative to `base_dir`.
calib::CalibrationInput LoadCalibrationInput(const std::string& path);
calib::CalibrationInput ParseCalibrationInput(std::string_view text, const std::string& name,
                                              const std::string& base_dir);

}  // namespace patlab::formats

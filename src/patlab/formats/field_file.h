// Field geometry files (docs/file-formats.md): the named lines, circles and points of a field
// (calib/field.h) that calibration inputs refer to.
#pragma once

#include <string>
#include <string_view>

#include "patlab/calib/field.h"

namespace patlab::formats {

// Reads a field file. Throws InputError "file:line: what is wrong; expected what" for the first
// problem.
calib::Field LoadField(const std::string& path);
calib::Field ParseField(std::string_view text, const std::string& source_name);

}  // namespace patlab::formats

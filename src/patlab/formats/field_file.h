// Field geometry files (docs/file-formats.md): the named lines, circles and points of a field
// (calib/field.h) that calibration inputs refer to.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "patlab/calib/field.h"

namespace patlab::formats {

// Reads a field file. Throws InputError "file:line: what is wrong; expected what" for the first
// problem.
calib::Field LoadField(const std::string& path);
calib::Field ParseField(std::string_view text, const std::string& source_name);

// The shipped field models (experiments/fields/*.toml under the data roots of io/data_path.h),
// parsed; by family, each family newest first (year descending, then name). A model that does
// not parse throws its InputError.
std::vector<calib::Field> ShippedFields(const std::vector<std::string>& roots);
// The families of the shipped models ("ssl", "vss"), sorted.
std::vector<std::string> FieldFamilies(const std::vector<std::string>& roots);
// Every shipped model of `family`, newest first; empty when there is no such family.
std::vector<calib::Field> FieldFamily(std::string_view family,
                                      const std::vector<std::string>& roots);

// The models `patlab setup --field NAME` fits: every shipped model of the family NAME, or the one
// model NAME (a shipped name or a file) with the other shipped models of its family as lenders,
// searched only for views to lend it (calib::AutoCalibrateFamily): a model whose search misses
// its camera borrows it from a model whose lines in view are alike.
struct SetupFieldModels {
  std::vector<calib::Field> fields;
  std::vector<calib::Field> lenders;
};
SetupFieldModels SetupFields(const std::string& name, const std::vector<std::string>& roots);

}  // namespace patlab::formats

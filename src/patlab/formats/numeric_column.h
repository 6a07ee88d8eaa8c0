// Reading one column of numbers: from a CSV file with a header row (column chosen by name) or
// from a plain file with one number a line. Used by `patlab stats` to load error samples.
//
// Rules (both formats): lines are split on '\n' (a trailing '\r' is dropped); blank lines and
// lines whose first non-blank character is '#' are skipped; cells are trimmed of spaces and
// tabs and parsed as decimal floating point (a leading '+' is allowed). Every failure throws
// patlab::InputError "file:line: what is wrong; expected what": a cell that is not a number,
// NaN or infinity, a CSV row without the column, a missing column name, no values at all.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "patlab/core/options.h"

namespace patlab::formats {

struct NumericColumnOptions {
  // Name of the CSV column to read (matched exactly after trimming and removing one pair of
  // double quotes). Empty: the file holds one number a line, no header.
  std::string column;
};
// column must be a name a header cell can have: no comma, no line break, no leading or trailing
// blank (cells are split on commas and trimmed), so that a typo is reported as such and not as
// "no column ... in the header".
std::vector<OptionsProblem> Check(const NumericColumnOptions& options);
void Validate(const NumericColumnOptions& options);

// Reads `path`; throws InputError if it cannot be opened. Both readers validate the options.
std::vector<double> ReadNumericColumn(const std::string& path,
                                      const NumericColumnOptions& options = {});

// The same on a stream; `source_name` is used in messages in place of the path.
std::vector<double> ParseNumericColumn(std::istream& in, const std::string& source_name,
                                       const NumericColumnOptions& options = {});

}  // namespace patlab::formats

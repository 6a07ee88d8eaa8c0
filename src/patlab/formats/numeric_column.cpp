#include "patlab/formats/numeric_column.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>

#include "patlab/core/error.h"
#include "patlab/io/csv.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {
namespace {

std::string_view TrimBlanks(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

double ParseCell(std::string_view cell, const FileLoc& loc, const std::string& where) {
  const std::optional<double> value = io::ParseDouble(cell);
  if (!value) {
    throw InputError(loc, "cannot read '" + EscapeForMessage(cell) + "'" + where +
                              " as a number; expected a decimal number such as 0.52 or -1.5e-3");
  }
  if (std::isinf(*value) && cell.find_first_of("iI") == std::string_view::npos) {  // overflow
    throw InputError(loc, "'" + EscapeForMessage(cell) + "'" + where +
                              " is out of range; expected a finite number");
  }
  if (!std::isfinite(*value)) {
    throw InputError(loc, "'" + EscapeForMessage(cell) + "'" + where +
                              " is not a finite number; expected a finite number (no NaN or "
                              "infinity)");
  }
  return *value;
}

// The plain format: one number a line.
std::vector<double> ParsePlain(std::string_view text, const std::string& source_name) {
  std::vector<double> values;
  int line_number = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view view = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    const std::string_view trimmed = TrimBlanks(view);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    const FileLoc loc{source_name, line_number};
    if (trimmed.find(',') != std::string_view::npos) {
      throw InputError(loc, "found a comma in '" + EscapeForMessage(trimmed) +
                                "'; expected one number a line (use --column NAME for CSV)");
    }
    values.push_back(ParseCell(trimmed, loc, ""));
  }
  return values;
}

// The CSV format: blank lines, '#' comment lines and blanks around cells allowed.
std::vector<double> ParseColumn(std::string_view text, const std::string& source_name,
                                const std::string& column) {
  std::vector<double> values;
  std::optional<size_t> index;
  io::CsvReadOptions options;
  options.skip_blank_lines = options.skip_comment_lines = options.trim_blanks = true;
  io::CsvParser parser(source_name, options, [&](const io::CsvRecord& r) {
    if (!index) {
      std::string names;
      for (size_t i = 0; i < r.cells.size() && !index; ++i) {
        if (r.cells[i] == column) index = i;
        names += (i ? ", " : "") + std::string(r.cells[i]);
      }
      if (!index) {
        throw InputError(r.Loc(),
                         "no column '" + EscapeForMessage(column) +
                             "' in the header; expected one of: " + EscapeForMessage(names, 300));
      }
      return;
    }
    if (*index >= r.cells.size()) {
      throw InputError(r.Loc(), "row has " + std::to_string(r.cells.size()) +
                                    " cells, no column '" + column + "'; expected at least " +
                                    std::to_string(*index + 1));
    }
    values.push_back(ParseCell(r.cells[*index], r.Loc(), " in column '" + column + "'"));
  });
  parser.Feed(text);
  parser.Finish();
  if (!index) {
    throw InputError(FileLoc{source_name, 0},
                     "no header row; expected a CSV header naming column '" + column + "'");
  }
  return values;
}

}  // namespace

std::vector<OptionsProblem> Check(const NumericColumnOptions& options) {
  OptionsChecker check;
  const std::string_view column = options.column;
  if (column.find_first_of(",\r\n") != std::string_view::npos || TrimBlanks(column) != column) {
    check.Fail("column", "column is \"" + options.column +
                             "\"; expected a CSV column name (no comma, line break, or leading "
                             "or trailing blank)");
  }
  return check.Take();
}

void Validate(const NumericColumnOptions& options) { ThrowFirstProblem(Check(options)); }

std::vector<double> ParseNumericColumn(std::istream& in, const std::string& source_name,
                                       const NumericColumnOptions& options) {
  Validate(options);
  const std::string text(std::istreambuf_iterator<char>(in), {});
  std::vector<double> values = options.column.empty()
                                   ? ParsePlain(text, source_name)
                                   : ParseColumn(text, source_name, options.column);
  if (values.empty()) {
    throw InputError(FileLoc{source_name, 0}, "no numbers found; expected at least one value");
  }
  return values;
}

std::vector<double> ReadNumericColumn(const std::string& path,
                                      const NumericColumnOptions& options) {
  Validate(options);
  io::CheckInputFile(path, "file of numbers", UINTMAX_MAX);
  std::ifstream in(path);
  if (!in) {
    throw InputError(FileLoc{path, 0}, "cannot open file; expected a readable file of numbers");
  }
  return ParseNumericColumn(in, path, options);
}

}  // namespace patlab::formats

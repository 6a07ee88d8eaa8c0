#include "patlab/formats/numeric_column.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string_view>

#include "patlab/core/error.h"
#include "patlab/io/toml_util.h"

namespace patlab::io {
namespace {

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

std::string_view Unquote(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

std::vector<std::string_view> SplitCsv(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(
        Trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

double ParseCell(std::string_view cell, const FileLoc& loc, const std::string& where) {
  std::string_view text = Unquote(cell);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    throw InputError(loc, "cannot read '" + EscapeForMessage(cell) + "'" + where +
                              " as a number; expected a decimal number such as 0.52 or -1.5e-3");
  }
  // from_chars leaves value untouched when out of range: strtod tells overflow (inf) from
  // underflow (0 or a subnormal, accepted).
  if (ec == std::errc::result_out_of_range) value = std::strtod(std::string(text).c_str(), nullptr);
  if (ec == std::errc::result_out_of_range && std::isinf(value)) {
    throw InputError(loc, "'" + EscapeForMessage(cell) + "'" + where +
                              " is out of range; expected a finite number");
  }
  if (!std::isfinite(value)) {
    throw InputError(loc, "'" + EscapeForMessage(cell) + "'" + where +
                              " is not a finite number; expected a finite number (no NaN or "
                              "infinity)");
  }
  return value;
}

}  // namespace

std::vector<OptionsProblem> Check(const NumericColumnOptions& options) {
  OptionsChecker check;
  const std::string_view column = options.column;
  if (column.find_first_of(",\r\n") != std::string_view::npos || Trim(column) != column) {
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
  std::vector<double> values;
  const bool csv = !options.column.empty();
  std::size_t column_index = 0;
  bool have_header = false;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::string_view view = line;
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    const std::string_view trimmed = Trim(view);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    const FileLoc loc{source_name, line_number};
    if (!csv) {
      if (trimmed.find(',') != std::string_view::npos) {
        throw InputError(loc, "found a comma in '" + EscapeForMessage(trimmed) +
                                  "'; expected one number a line (use --column NAME for CSV)");
      }
      values.push_back(ParseCell(trimmed, loc, ""));
      continue;
    }
    const std::vector<std::string_view> cells = SplitCsv(view);
    if (!have_header) {
      std::string names;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (Unquote(cells[i]) == options.column) {
          column_index = i;
          have_header = true;
          break;
        }
        names += (i ? ", " : "") + std::string(Unquote(cells[i]));
      }
      if (!have_header) {
        throw InputError(loc,
                         "no column '" + EscapeForMessage(options.column) +
                             "' in the header; expected one of: " + EscapeForMessage(names, 300));
      }
      continue;
    }
    if (column_index >= cells.size()) {
      throw InputError(loc, "row has " + std::to_string(cells.size()) + " cells, no column '" +
                                options.column + "'; expected at least " +
                                std::to_string(column_index + 1));
    }
    values.push_back(ParseCell(cells[column_index], loc, " in column '" + options.column + "'"));
  }
  if (csv && !have_header) {
    throw InputError(FileLoc{source_name, 0},
                     "no header row; expected a CSV header naming column '" + options.column + "'");
  }
  if (values.empty()) {
    throw InputError(FileLoc{source_name, 0}, "no numbers found; expected at least one value");
  }
  return values;
}

std::vector<double> ReadNumericColumn(const std::string& path,
                                      const NumericColumnOptions& options) {
  Validate(options);
  CheckInputFile(path, "file of numbers", UINTMAX_MAX);
  std::ifstream in(path);
  if (!in) {
    throw InputError(FileLoc{path, 0}, "cannot open file; expected a readable file of numbers");
  }
  return ParseNumericColumn(in, path, options);
}

}  // namespace patlab::io

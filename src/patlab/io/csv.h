// CSV, the one reader and writer of every CSV file patlab reads or writes (RFC 4180).
//
// Writing: a cell is quoted when it holds a comma, a double quote (written twice), CR or LF, or
// begins or ends with a space or tab; every other cell is written as it is, so a file whose cells
// need no quoting keeps its bytes. Rows end in "\n".
//
// Reading: quoted cells (embedded commas, doubled quotes, line breaks inside quotes), CRLF and LF
// line ends, a UTF-8 byte order mark at the start. What else a file may hold is the format's
// choice (CsvReadOptions): blank lines, '#' comment lines, blanks around cells. Every error is an
// InputError naming the file, the line and, where there is one, the column (1-based):
//   "tracks.csv:12: column 3 ('x_mm'): 'abc' is not a number; expected a finite number".
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/error.h"

namespace patlab::io {

// ---- writing ----

// True when `cell` must be quoted (see above).
bool CsvNeedsQuotes(std::string_view cell);

// Appends `cell` to `out`, quoted when it needs to be.
void AppendCsvCell(std::string_view cell, std::string* out);

// Builds rows: cells separated by commas, each quoted when it needs to be, rows ended by "\n".
class CsvWriter {
 public:
  explicit CsvWriter(std::string* out) : out_(out) {}
  CsvWriter& Cell(std::string_view cell);
  CsvWriter& Cell(int64_t value);
  // Several cells in order.
  CsvWriter& Cells(std::initializer_list<std::string_view> cells);
  void EndRow();

 private:
  std::string* out_;
  bool row_started_ = false;
};

// One row of `cells` with its "\n".
std::string CsvRow(std::initializer_list<std::string_view> cells);
std::string CsvRow(std::span<const std::string> cells);

// ---- reading ----

// What a format allows besides RFC 4180 records. The defaults are strict.
struct CsvReadOptions {
  bool skip_blank_lines = false;    // lines of nothing but blanks are not records
  bool skip_comment_lines = false;  // lines whose first non-blank character is '#' are not records
  bool trim_blanks = false;         // spaces and tabs around a cell (outside its quotes) dropped
};

// One record: its cells, where it starts, and where it comes from.
struct CsvRecord {
  const std::string* source = nullptr;  // the file name used in messages
  int line = 0;                         // 1-based line on which the record starts
  std::vector<std::string_view> cells;  // valid until the next record

  FileLoc Loc() const { return {*source, line}; }
  // Throws "source:line: row has N cells; expected M (...what)" unless it has exactly `count`.
  void RequireCells(size_t count, std::string_view what) const;
};

// A push parser: Feed() the bytes in pieces of any size (a record may span pieces), then
// Finish(). Each complete record is passed to `on_record`.
class CsvParser {
 public:
  using RecordHandler = std::function<void(const CsvRecord&)>;
  CsvParser(std::string source, CsvReadOptions options, RecordHandler on_record);

  void Feed(std::string_view bytes);
  // Ends the input: the last record without a line end, or an unterminated quote (InputError).
  void Finish();

 private:
  enum class State {
    kLineStart,
    kComment,
    kFieldStart,
    kUnquoted,
    kQuoted,
    kQuoteInQuoted,
    kAfterQuoted
  };
  void Step(char c);
  bool AtLineStart(char c);  // true when `c` is consumed there (a comment, a leading blank)
  void InField(char c);
  void InQuotes(char c);
  void AfterQuote(char c);
  void EndField();
  void EndRecord();
  [[noreturn]] void Fail(const std::string& what) const;

  std::string source_;
  CsvReadOptions options_;
  RecordHandler on_record_;
  State state_ = State::kLineStart;
  bool at_start_ = true;       // before the first byte (a byte order mark may follow)
  bool pending_cr_ = false;    // a CR outside quotes not yet known to end a line
  std::string bom_;            // bytes of a possible byte order mark seen so far
  std::string bytes_;          // the cells of the record being read, back to back
  std::vector<size_t> ends_;   // end of each finished cell in bytes_
  size_t field_begin_ = 0;     // where the current cell starts in bytes_
  bool field_quoted_ = false;  // the current cell was quoted
  bool record_blank_ = true;   // nothing but blanks so far in the record
  int line_ = 1;               // the line being read
  int record_line_ = 1;        // the line the record started on
  int quote_line_ = 0;         // the line on which the open quote started
  CsvRecord record_;
};

// Every record of `text`, the header (if any) included, as text.
std::vector<std::vector<std::string>> ParseCsvRecords(std::string_view text,
                                                      const std::string& source,
                                                      const CsvReadOptions& options = {});

// A whole CSV text: its first record is the header, the others its rows.
struct CsvTable {
  std::string source;
  int header_line = 0;
  std::vector<std::string> header;
  struct Row {
    int line = 0;
    std::vector<std::string> cells;
  };
  std::vector<Row> rows;

  // Index of the column named `name`, or nullopt.
  std::optional<size_t> Find(std::string_view name) const;
  // Index of `name`; throws "source:line: no column 'name' in the header; expected <expected>".
  size_t Require(std::string_view name, std::string_view expected) const;
};

// Parses `text`; the first record is the header. With `same_width`, every row must have as many
// cells as the header.
CsvTable ParseCsv(std::string_view text, const std::string& source, const CsvReadOptions& options,
                  bool same_width = true);

// The number in cell `index` of `record` (from_chars: the C locale's form whatever the locale;
// a leading '+' allowed). Throws
// "source:line: column N ('name'): 'cell' is not a number; expected a finite number".
double CsvNumber(const CsvRecord& record, size_t index, std::string_view column_name);
// The same for a cell of a table row.
double CsvNumber(const CsvTable& table, const CsvTable::Row& row, size_t index);
// An integer cell: "... 'cell' is not an integer; expected <expected>".
int64_t CsvInteger(const CsvRecord& record, size_t index, std::string_view column_name,
                   std::string_view expected);

// Reads a number written by patlab or a person: a decimal or exponent form as from_chars takes
// it, with an optional leading '+'; nullopt when `text` is not one whole number. Out-of-range
// values become +-inf (overflow) or 0 (underflow), as strtod gives them.
std::optional<double> ParseDouble(std::string_view text);

}  // namespace patlab::io

#include "patlab/io/csv.h"

#include <charconv>
#include <cmath>
#include <limits>

namespace patlab::io {

namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// Text in single quotes for a message (by append: GCC 12's -Wrestrict misfires on
// "literal" + std::string chains).
std::string Quote(std::string_view text) {
  std::string out = "'";
  out.append(EscapeForMessage(text, 60)).append("'");
  return out;
}

std::string ColumnPrefix(size_t index, std::string_view name) {
  std::string out = "column " + std::to_string(index + 1);
  if (!name.empty()) out += " (" + Quote(name) + ")";
  return out + ": ";
}

// The decimal exponent of the first significant digit of a number text, roughly: enough to tell
// an overflow (> 0) from an underflow (< 0) when from_chars reports the value out of range.
bool Overflows(std::string_view text) {
  long exponent = 0;
  const size_t e = text.find_first_of("eE");
  if (e != std::string_view::npos) {
    std::string_view digits = text.substr(e + 1);
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    std::from_chars(digits.data(), digits.data() + digits.size(), exponent);
  }
  const std::string_view mantissa = text.substr(0, e);
  const size_t first = mantissa.find_first_of("123456789");
  const size_t point = std::min(mantissa.find('.'), mantissa.size());
  if (first == std::string_view::npos) return false;
  const long lead =
      first < point ? static_cast<long>(point - first) - 1 : -static_cast<long>(first - point);
  return exponent + lead > 0;
}

}  // namespace

// ---- writing ----

bool CsvNeedsQuotes(std::string_view cell) {
  if (cell.empty()) return false;
  if (IsBlank(cell.front()) || IsBlank(cell.back())) return true;
  return cell.find_first_of(",\"\r\n") != std::string_view::npos;
}

void AppendCsvCell(std::string_view cell, std::string* out) {
  if (!CsvNeedsQuotes(cell)) {
    out->append(cell);
    return;
  }
  out->push_back('"');
  for (const char c : cell) {
    if (c == '"') out->push_back('"');
    out->push_back(c);
  }
  out->push_back('"');
}

CsvWriter& CsvWriter::Cell(std::string_view cell) {
  if (row_started_) out_->push_back(',');
  row_started_ = true;
  AppendCsvCell(cell, out_);
  return *this;
}

CsvWriter& CsvWriter::Cell(int64_t value) { return Cell(std::string_view(std::to_string(value))); }

CsvWriter& CsvWriter::Cells(std::initializer_list<std::string_view> cells) {
  for (const std::string_view cell : cells) Cell(cell);
  return *this;
}

void CsvWriter::EndRow() {
  out_->push_back('\n');
  row_started_ = false;
}

std::string CsvRow(std::initializer_list<std::string_view> cells) {
  std::string out;
  CsvWriter(&out).Cells(cells).EndRow();
  return out;
}

std::string CsvRow(std::span<const std::string> cells) {
  std::string out;
  CsvWriter w(&out);
  for (const std::string& cell : cells) w.Cell(cell);
  w.EndRow();
  return out;
}

// ---- reading ----

void CsvRecord::RequireCells(size_t count, std::string_view what) const {
  if (cells.size() == count) return;
  throw InputError(Loc(), "row has " + std::to_string(cells.size()) + " cells; expected " +
                              std::to_string(count) + " (" + std::string(what) + ")");
}

CsvParser::CsvParser(std::string source, CsvReadOptions options, RecordHandler on_record)
    : source_(std::move(source)), options_(options), on_record_(std::move(on_record)) {
  record_.source = &source_;
}

void CsvParser::Fail(const std::string& what) const {
  throw InputError(FileLoc{source_, state_ == State::kQuoted ? quote_line_ : line_}, what);
}

void CsvParser::Feed(std::string_view bytes) {
  static constexpr std::string_view kBom = "\xEF\xBB\xBF";
  for (const char c : bytes) {
    if (at_start_) {
      bom_.push_back(c);
      if (kBom.substr(0, bom_.size()) == bom_) {
        if (bom_.size() == kBom.size()) at_start_ = false;
        continue;
      }
      at_start_ = false;
      const std::string held = std::move(bom_);
      for (const char h : held) Step(h);
      continue;
    }
    Step(c);
  }
}

void CsvParser::EndField() {
  if (!field_quoted_ && options_.trim_blanks) {
    while (bytes_.size() > field_begin_ && IsBlank(bytes_.back())) bytes_.pop_back();
  }
  ends_.push_back(bytes_.size());
  field_begin_ = bytes_.size();
  field_quoted_ = false;
}

void CsvParser::EndRecord() {
  EndField();
  const bool blank = record_blank_ && ends_.size() == 1;
  if (!(blank && options_.skip_blank_lines)) {
    record_.line = record_line_;
    record_.cells.clear();
    size_t begin = 0;
    for (const size_t end : ends_) {
      record_.cells.emplace_back(bytes_.data() + begin, end - begin);
      begin = end;
    }
    on_record_(record_);
  }
  bytes_.clear();
  ends_.clear();
  field_begin_ = 0;
  record_blank_ = true;
  state_ = State::kLineStart;
}

void CsvParser::Step(char c) {
  if (pending_cr_) {
    pending_cr_ = false;
    if (c != '\n') {  // a lone CR outside quotes is a character of the cell
      bytes_.push_back('\r');
      record_blank_ = false;
      if (state_ == State::kFieldStart) state_ = State::kUnquoted;
    }
  }
  if (c == '\n') ++line_;
  switch (state_) {
    case State::kLineStart:
      if (!AtLineStart(c)) InField(c);
      return;
    case State::kFieldStart:
    case State::kUnquoted:
      InField(c);
      return;
    case State::kComment:
      if (c == '\n') {
        bytes_.clear();
        state_ = State::kLineStart;
      }
      return;
    case State::kQuoted:
    case State::kQuoteInQuoted:
      InQuotes(c);
      return;
    case State::kAfterQuoted:
      AfterQuote(c);
      return;
  }
}

bool CsvParser::AtLineStart(char c) {
  record_line_ = line_ - (c == '\n' ? 1 : 0);
  if (options_.skip_comment_lines && c == '#') {
    state_ = State::kComment;
    return true;
  }
  if (IsBlank(c)) {  // kept: the start of an unquoted cell unless trim_blanks drops it
    bytes_.push_back(c);
    return true;
  }
  state_ = State::kFieldStart;
  if (options_.trim_blanks) bytes_.clear();
  return false;
}

void CsvParser::InField(char c) {
  if (state_ == State::kFieldStart) {
    if (c == '"' && bytes_.size() == field_begin_) {  // after blanks kept, a quote is text
      state_ = State::kQuoted;
      field_quoted_ = true;
      quote_line_ = line_;
      record_blank_ = false;
      return;
    }
    if (IsBlank(c) && options_.trim_blanks) return;
    state_ = State::kUnquoted;
  }
  if (c == ',') {
    EndField();
    record_blank_ = false;
    state_ = State::kFieldStart;
  } else if (c == '\n') {
    EndRecord();
  } else if (c == '\r') {
    pending_cr_ = true;
  } else {
    if (!IsBlank(c)) record_blank_ = false;
    bytes_.push_back(c);
  }
}

void CsvParser::InQuotes(char c) {
  if (state_ == State::kQuoted) {
    if (c == '"') {
      state_ = State::kQuoteInQuoted;
    } else {
      bytes_.push_back(c);
    }
    return;
  }
  if (c == '"') {  // a doubled quote
    bytes_.push_back('"');
    state_ = State::kQuoted;
    return;
  }
  state_ = State::kAfterQuoted;
  AfterQuote(c);
}

void CsvParser::AfterQuote(char c) {
  if (c == ',') {
    EndField();
    state_ = State::kFieldStart;
  } else if (c == '\n') {
    EndRecord();
  } else if (c == '\r') {
    pending_cr_ = true;
  } else if (!(IsBlank(c) && options_.trim_blanks)) {
    Fail(ColumnPrefix(ends_.size(), "") + "'" + EscapeForMessage(std::string_view(&c, 1)) +
         "' after the closing quote; expected ',' or the end of the line");
  }
}

void CsvParser::Finish() {
  if (at_start_ && !bom_.empty()) {
    at_start_ = false;
    const std::string held = std::move(bom_);
    for (const char h : held) Step(h);
  }
  if (state_ == State::kQuoted) {
    Fail(ColumnPrefix(ends_.size(), "") +
         "quoted cell not closed; expected a '\"' before the end of the file");
  }
  const bool pending = pending_cr_;
  pending_cr_ = false;
  if (pending) Step('\n');  // a last CR ends the last line
  if (state_ != State::kLineStart && state_ != State::kComment) EndRecord();
  if (state_ == State::kLineStart && !bytes_.empty()) EndRecord();  // a last line of blanks
}

std::vector<std::vector<std::string>> ParseCsvRecords(std::string_view text,
                                                      const std::string& source,
                                                      const CsvReadOptions& options) {
  std::vector<std::vector<std::string>> records;
  CsvParser parser(source, options, [&](const CsvRecord& r) {
    records.emplace_back(r.cells.begin(), r.cells.end());
  });
  parser.Feed(text);
  parser.Finish();
  return records;
}

std::optional<size_t> CsvTable::Find(std::string_view name) const {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  return std::nullopt;
}

size_t CsvTable::Require(std::string_view name, std::string_view expected) const {
  if (const auto index = Find(name)) return *index;
  throw InputError(
      FileLoc{source, header_line},
      "no column " + Quote(name) + " in the header; expected " + std::string(expected));
}

CsvTable ParseCsv(std::string_view text, const std::string& source, const CsvReadOptions& options,
                  bool same_width) {
  CsvTable table;
  table.source = source;
  bool have_header = false;
  CsvParser parser(source, options, [&](const CsvRecord& r) {
    if (!have_header) {
      have_header = true;
      table.header_line = r.line;
      table.header.assign(r.cells.begin(), r.cells.end());
      return;
    }
    if (same_width) r.RequireCells(table.header.size(), "as many as the header");
    table.rows.push_back({r.line, std::vector<std::string>(r.cells.begin(), r.cells.end())});
  });
  parser.Feed(text);
  parser.Finish();
  if (!have_header) {
    throw InputError(FileLoc{source, 0}, "no header row; expected a CSV header naming the columns");
  }
  return table;
}

std::optional<double> ParseDouble(std::string_view text) {
  std::string_view s = text;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty() || s.front() == '+') return std::nullopt;
  double value = 0.0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, value);
  if (ptr != end) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    const bool negative = s.front() == '-';
    value = Overflows(s) ? std::numeric_limits<double>::infinity() : 0.0;
    return negative ? -value : value;
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

double CsvNumber(const CsvRecord& record, size_t index, std::string_view column_name) {
  const std::string_view cell = record.cells.at(index);
  const std::optional<double> v = ParseDouble(cell);
  if (!v || !std::isfinite(*v)) {
    throw InputError(record.Loc(), ColumnPrefix(index, column_name) + Quote(cell) +
                                       (v ? " is not a finite number" : " is not a number") +
                                       "; expected a finite number");
  }
  return *v;
}

double CsvNumber(const CsvTable& table, const CsvTable::Row& row, size_t index) {
  CsvRecord record;
  record.source = &table.source;
  record.line = row.line;
  record.cells.assign(row.cells.begin(), row.cells.end());
  return CsvNumber(record, index, table.header.at(index));
}

int64_t CsvInteger(const CsvRecord& record, size_t index, std::string_view column_name,
                   std::string_view expected) {
  const std::string_view cell = record.cells.at(index);
  std::string_view s = cell;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) {
    throw InputError(record.Loc(), ColumnPrefix(index, column_name) + Quote(cell) +
                                       " is not an integer; expected " + std::string(expected));
  }
  return v;
}

}  // namespace patlab::io

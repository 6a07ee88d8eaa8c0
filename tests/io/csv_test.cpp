// Tests of the one CSV reader and writer (src/patlab/io/csv.h).
#include "patlab/io/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../expect_error.h"

namespace patlab::io {
namespace {

using Rows = std::vector<std::vector<std::string>>;

Rows ReadAll(std::string_view text, const CsvReadOptions& options = {}, size_t piece = 0) {
  Rows rows;
  CsvParser parser("t.csv", options,
                   [&](const CsvRecord& r) { rows.emplace_back(r.cells.begin(), r.cells.end()); });
  if (piece == 0) {
    parser.Feed(text);
  } else {
    for (size_t i = 0; i < text.size(); i += piece) parser.Feed(text.substr(i, piece));
  }
  parser.Finish();
  return rows;
}

TEST(CsvWriter, QuotesOnlyWhatNeedsIt) {
  EXPECT_EQ(CsvRow({"a", "1.5", "", "x_mm"}), "a,1.5,,x_mm\n");
  EXPECT_EQ(CsvRow({"a,b", "say \"hi\"", "two\nlines", "cr\r", " lead", "trail\t"}),
            "\"a,b\",\"say \"\"hi\"\"\",\"two\nlines\",\"cr\r\",\" lead\",\"trail\t\"\n");
  EXPECT_EQ(CsvRow({"in side", "Ünïcödé,名前"}), "in side,\"Ünïcödé,名前\"\n");
  std::string out;
  CsvWriter(&out).Cell("frame").Cell(int64_t{-7}).EndRow();
  EXPECT_EQ(out, "frame,-7\n");
}

TEST(CsvReader, RoundTripsEveryKindOfCell) {
  const Rows rows = {{"plain", "a,b", "say \"hi\"", "two\nlines", "cr\rin", " lead", "trail "},
                     {"", "", "", "", "", "", ""},
                     {"Ünïcödé,名前", "x", "\"", ",", "\r\n", "  ", "#not a comment"}};
  std::string text;
  for (const auto& row : rows) text += CsvRow(row);
  EXPECT_EQ(ReadAll(text), rows);
  for (const size_t piece : {1u, 2u, 3u, 7u}) EXPECT_EQ(ReadAll(text, {}, piece), rows) << piece;
  CsvReadOptions lenient;
  lenient.trim_blanks = lenient.skip_blank_lines = lenient.skip_comment_lines = true;
  EXPECT_EQ(ReadAll(text, lenient), rows);
}

TEST(CsvReader, CrlfBomAndLastLineWithoutEnd) {
  const Rows expected = {{"a", "b"}, {"1", "x,y"}, {"2", ""}};
  EXPECT_EQ(ReadAll("\xEF\xBB\xBF"
                    "a,b\r\n1,\"x,y\"\r\n2,\r\n"),
            expected);
  EXPECT_EQ(ReadAll("\xEF\xBB\xBF"
                    "a,b\r\n1,\"x,y\"\r\n2,",
                    {}, 1),
            expected);
  EXPECT_EQ(ReadAll("a,b\n1,\"x,y\"\n2,\r"), expected);
  EXPECT_EQ(ReadAll("\xEF\xBB"), Rows({{"\xEF\xBB"}}));  // a cut mark is text
  EXPECT_EQ(ReadAll(""), Rows());
}

TEST(CsvReader, BlankAndCommentLinesOnlyWhereAllowed) {
  const std::string text = "a,b\n\n  # note\n1, 2 \n \"q\" ,3\n   \n";
  EXPECT_EQ(ReadAll(text),
            Rows({{"a", "b"}, {""}, {"  # note"}, {"1", " 2 "}, {" \"q\" ", "3"}, {"   "}}));
  CsvReadOptions lenient;
  lenient.trim_blanks = lenient.skip_blank_lines = lenient.skip_comment_lines = true;
  EXPECT_EQ(ReadAll(text, lenient), Rows({{"a", "b"}, {"1", "2"}, {"q", "3"}}));
}

TEST(CsvReader, LineNumbersCountLinesInsideQuotes) {
  std::vector<int> lines;
  CsvParser parser("t.csv", {}, [&](const CsvRecord& r) { lines.push_back(r.line); });
  parser.Feed("h\n\"two\nlines\"\nnext\r\nlast");
  parser.Finish();
  EXPECT_EQ(lines, std::vector<int>({1, 2, 4, 5}));
}

TEST(CsvReader, ErrorsNameFileLineAndColumn) {
  EXPECT_INPUT_ERROR(ReadAll("a,b\n1,\"open\n2,3\n"),
                     "t.csv:2: column 2: quoted cell not closed; expected a '\"' before the end "
                     "of the file");
  EXPECT_INPUT_ERROR(ReadAll("a,b\n\"x\"y,2\n"),
                     "t.csv:2: column 1: 'y' after the closing quote; expected ',' or the end of "
                     "the line");
  EXPECT_INPUT_ERROR(ParseCsv("a,b\n1,2\n1,2,3\n", "t.csv", {}),
                     "t.csv:3: row has 3 cells; expected 2 (as many as the header)");
  const CsvTable table = ParseCsv("frame,x_mm\n1,2.5\n2,abc\n", "tracks.csv", {});
  EXPECT_INPUT_ERROR(table.Require("y_mm", "a y_mm column"),
                     "tracks.csv:1: no column 'y_mm' in the header; expected a y_mm column");
  EXPECT_EQ(table.Require("x_mm", ""), 1u);
  EXPECT_EQ(CsvNumber(table, table.rows[0], 1), 2.5);
  EXPECT_INPUT_ERROR(CsvNumber(table, table.rows[1], 1),
                     "tracks.csv:3: column 2 ('x_mm'): 'abc' is not a number; expected a finite "
                     "number");
  EXPECT_INPUT_ERROR(ParseCsv("", "e.csv", {}),
                     "e.csv: no header row; expected a CSV header naming the columns");
}

TEST(ParseDouble, WholeNumbersInTheCLocaleForm) {
  EXPECT_EQ(ParseDouble("+1.5e3"), 1500.0);
  EXPECT_EQ(ParseDouble("-0.25"), -0.25);
  EXPECT_FALSE(ParseDouble("1,5"));
  EXPECT_FALSE(ParseDouble(""));
  EXPECT_FALSE(ParseDouble("++1"));
  EXPECT_FALSE(ParseDouble("1.5 "));
  EXPECT_EQ(ParseDouble("1e999"), INFINITY);
  EXPECT_EQ(ParseDouble("-1e999"), -INFINITY);
  EXPECT_EQ(ParseDouble("1e-999"), 0.0);
  EXPECT_EQ(ParseDouble("12345e-320"), 12345e-320);  // a subnormal is in range
  EXPECT_EQ(ParseDouble("0.00001e-400"), 0.0);
}

}  // namespace
}  // namespace patlab::io

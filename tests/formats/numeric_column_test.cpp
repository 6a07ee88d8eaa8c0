#include "patlab/formats/numeric_column.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "patlab/core/error.h"

namespace patlab::formats {
namespace {

std::vector<double> Parse(const std::string& text, const std::string& column = "") {
  std::istringstream in(text);
  NumericColumnOptions options;
  options.column = column;
  return ParseNumericColumn(in, "in.txt", options);
}

TEST(NumericColumn, ReadsOneNumberALine) {
  EXPECT_EQ(Parse("1\n  -2.5\t\n# comment\n\n+3e-2\r\n0.1\n"),
            (std::vector<double>{1.0, -2.5, 3e-2, 0.1}));
  // 17 significant digits round-trip exactly.
  EXPECT_EQ(Parse("0.10000000000000001\n")[0], 0.1);
}

TEST(NumericColumn, ReadsANamedCsvColumn) {
  EXPECT_EQ(Parse("# run 3\nx,\"theta\", y\n1, 0.5 ,9\n2,-0.25,9\n\n", "theta"),
            (std::vector<double>{0.5, -0.25}));
  EXPECT_EQ(Parse("x,y\n1,2\n", "y"), (std::vector<double>{2.0}));
}

TEST(NumericColumn, ErrorsNameFileLineAndExpectation) {
  EXPECT_INPUT_ERROR(
      Parse("1\n2\nabc\n"),
      "in.txt:3: cannot read 'abc' as a number; expected a decimal number such as 0.52 or "
      "-1.5e-3");
  EXPECT_INPUT_ERROR(
      Parse("1\n1.5x\n"),
      "in.txt:2: cannot read '1.5x' as a number; expected a decimal number such as 0.52 or "
      "-1.5e-3");
  EXPECT_INPUT_ERROR(Parse("1\nnan\n"),
                     "in.txt:2: 'nan' is not a finite number; expected a finite number (no NaN or "
                     "infinity)");
  EXPECT_INPUT_ERROR(Parse("-inf\n"),
                     "in.txt:1: '-inf' is not a finite number; expected a finite number (no NaN or "
                     "infinity)");
  EXPECT_INPUT_ERROR(Parse("1e400\n"),
                     "in.txt:1: '1e400' is out of range; expected a finite number");
  EXPECT_INPUT_ERROR(Parse("# nothing\n\n"),
                     "in.txt: no numbers found; expected at least one value");
  EXPECT_INPUT_ERROR(
      Parse("1,2\n"),
      "in.txt:1: found a comma in '1,2'; expected one number a line (use --column NAME "
      "for CSV)");
  EXPECT_INPUT_ERROR(Parse("a,b\n1,2\n", "c"),
                     "in.txt:1: no column 'c' in the header; expected one of: a, b");
  EXPECT_INPUT_ERROR(Parse("a,b\n1,2\n3\n", "b"),
                     "in.txt:3: row has 1 cells, no column 'b'; expected at least 2");
  EXPECT_INPUT_ERROR(
      Parse("a,b\n1,\n", "b"),
      "in.txt:2: cannot read '' in column 'b' as a number; expected a decimal number such "
      "as 0.52 or -1.5e-3");
  EXPECT_INPUT_ERROR(Parse("a,b\n", "b"), "in.txt: no numbers found; expected at least one value");
  EXPECT_INPUT_ERROR(Parse("", "b"),
                     "in.txt: no header row; expected a CSV header naming column 'b'");
}

TEST(NumericColumn, ColumnNamesThatNoHeaderCellCanHaveAreRejected) {
  EXPECT_TRUE(Check(NumericColumnOptions{}).empty());
  EXPECT_TRUE(Check(NumericColumnOptions{"theta err"}).empty());
  const std::string expected =
      "\"; expected a CSV column name (no comma, line break, or leading or trailing blank)";
  EXPECT_INPUT_ERROR(Parse("a,b\n1,2\n", "a,b"), "column is \"a,b" + expected);
  EXPECT_INPUT_ERROR(Parse("a\n1\n", " a"), "column is \" a" + expected);
  EXPECT_INPUT_ERROR(ReadNumericColumn("/nonexistent", {"x\n"}), "column is \"x\n" + expected);
}

TEST(NumericColumn, MissingFile) {
  EXPECT_INPUT_ERROR(
      ReadNumericColumn("/nonexistent/file.txt"),
      "/nonexistent/file.txt: cannot open file; expected a readable file of numbers");
}

}  // namespace
}  // namespace patlab::formats

// CSV and numbers as text end to end: a frame path with a comma and a quote goes through `patlab
// detect` and its CSV is read back with every column in place; results under a German locale
// (a decimal comma) are the bytes of the C locale.
#include <gtest/gtest.h>

#include <clocale>
#include <filesystem>
#include <string>

#include "../test_util.h"
#include "patlab/io/csv.h"

namespace patlab {
namespace {

using testing::kGolden;
using testing::kPatlab;
using testing::kSource;
using testing::RunCommand;

std::string DetectFlags() {
  return " --thresholds " + kGolden + "ssl-frame.thresholds.toml --calibration " + kGolden +
         "ssl-frame.calibration.toml --settings " + kGolden + "ssl-frame.detector.toml";
}

TEST(CsvCli, FramePathWithCommaAndQuoteKeepsEveryColumnInPlace) {
  testing::TempDir dir;
  const std::string frame = dir.Path("run 1, \"best\" frame.png");
  std::filesystem::copy_file(kGolden + "ssl-frame.png", frame);
  const auto r = RunCommand(kPatlab + " detect '" + frame + "'" + DetectFlags() + " --out " +
                            dir.Path("d") + " --track");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = testing::ReadFile(dir.Path("d/detections.csv"));
  std::string quoted = "\"";  // the path as the writer quotes it (by append: GCC 12 -Wrestrict)
  quoted.append(dir.Path("run 1, \"\"best\"\" frame.png")).append("\",");
  EXPECT_NE(text.find(quoted), std::string::npos) << text;
  const io::CsvTable table = io::ParseCsv(text, "d.csv", {});  // same width as the header
  ASSERT_EQ(table.rows.size(), 10u);
  const size_t frame_column = table.Require("frame", ""), x = table.Require("x_mm", "");
  for (const io::CsvTable::Row& row : table.rows) {
    EXPECT_EQ(row.cells[frame_column], frame);
    EXPECT_EQ(row.cells[table.Require("pattern", "")], "ssl-standard");
    EXPECT_TRUE(io::ParseDouble(row.cells[x]).has_value()) << row.cells[x];
  }
  const io::CsvTable track = io::ParseCsv(testing::ReadFile(dir.Path("d/track.csv")), "t.csv", {});
  EXPECT_EQ(track.rows.size(), 10u);
}

// The locale a user's shell has must not reach a result file. patlab never calls setlocale, and
// its numbers go through std::to_chars (tests/core/format_test.cpp sets the locale in-process).
TEST(CsvCli, GermanLocaleGivesTheBytesOfTheCLocale) {
  const std::string saved = std::setlocale(LC_ALL, nullptr);
  const bool have_german = std::setlocale(LC_ALL, "de_DE.UTF-8") != nullptr;
  std::setlocale(LC_ALL, saved.c_str());
  if (!have_german) GTEST_SKIP() << "locale de_DE.UTF-8 is not installed (scripts/setup.sh)";
  testing::TempDir dir;
  for (const std::string locale : {"C", "de_DE.UTF-8"}) {
    const std::string out = dir.Path(locale);
    const std::string env = "LC_ALL=" + locale + " ";
    const auto sim = RunCommand(env + kPatlab + " simulate " + kSource +
                                "/experiments/fig5.toml --trials 2000 -q --out " + out);
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto cmp = RunCommand(env + kPatlab + " compare simple linear --out " + out + "/cmp -q");
    ASSERT_EQ(cmp.exit_code, 0) << cmp.err;
    const auto an = RunCommand(env + kPatlab + " analyze " + kSource +
                               "/results/analyze/track.csv --out " + out + "/an -q");
    ASSERT_EQ(an.exit_code, 0) << an.err;
  }
  for (const char* file : {"fig5.csv", "cmp/compare.csv", "cmp/compare.txt", "an/analyze.csv",
                           "an/analyze_errors.csv"}) {
    SCOPED_TRACE(file);
    const std::string c = testing::ReadFile(dir.Path("C") + "/" + file);
    EXPECT_FALSE(c.empty());
    EXPECT_EQ(testing::ReadFile(dir.Path("de_DE.UTF-8") + "/" + file), c);
  }
}

}  // namespace
}  // namespace patlab

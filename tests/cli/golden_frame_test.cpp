// The golden frame (tests/data/golden, docs/render.md): a frame patlab renders itself, with the
// SSL standard pattern at known poses, committed with its expected detections, so the whole
// real-frame path -- patlab render, then patlab detect: PNG -> colour classes -> regions ->
// blobs in mm -> detector -> CSV -- is tested on every clone. The binary is run as a user would.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/core/geometry.h"
#include "patlab/vision/frame_io.h"

namespace patlab {
namespace {

using testing::CommandResult;
using testing::kGolden;
using testing::kPatlab;
using testing::ReadFile;
using testing::RunCommand;
using testing::TempDir;

// A CSV file as rows of named cells (the detect CSV may gain columns: compare by name).
using Row = std::map<std::string, std::string>;
struct Csv {
  std::vector<std::string> header;
  std::vector<Row> rows;
};

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

Csv ParseCsv(const std::string& text) {
  Csv csv;
  std::stringstream lines(text);
  std::string line;
  if (std::getline(lines, line)) csv.header = SplitCells(line);
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = SplitCells(line);
    EXPECT_EQ(cells.size(), csv.header.size()) << line;
    Row row;
    for (size_t i = 0; i < cells.size() && i < csv.header.size(); ++i)
      row[csv.header[i]] = cells[i];
    csv.rows.push_back(row);
  }
  return csv;
}

double Number(const Row& row, const std::string& column) {
  const auto it = row.find(column);
  EXPECT_NE(it, row.end()) << "no column " << column;
  return it == row.end() ? NAN : std::stod(it->second);
}

std::string Cell(const Row& row, const std::string& column) {
  const auto it = row.find(column);
  EXPECT_NE(it, row.end()) << "no column " << column;
  return it == row.end() ? "" : it->second;
}

CommandResult DetectGolden() {
  return RunCommand(kPatlab + " detect " + kGolden + "ssl-frame.png --thresholds " + kGolden +
                    "ssl-frame.thresholds.toml --calibration " + kGolden +
                    "ssl-frame.calibration.toml --settings " + kGolden + "ssl-frame.detector.toml");
}

// (a) patlab render reproduces the committed frame and truth. Pixels, not bytes, are compared:
// PNG encoders may compress differently, and another CPU or libm may round the sub-sample
// positions, the blur sums or the Box-Muller log / cos differently in the last bit. Such a
// difference moves a level across a rounding boundary only when the exact value lies within
// ~1e-12 of n + 1/2, so it changes a pixel by at most 1 level and almost never: we allow
// max |diff| <= 1 and fewer than 0.1% of the values differing. A changed renderer (geometry,
// colours, blur, noise or seed) changes most noisy values by several levels.
TEST(GoldenFrame, RenderReproducesTheCommittedFrameAndTruth) {
  TempDir dir;
  const CommandResult r =
      RunCommand(kPatlab + " render " + kGolden + "ssl-frame.toml --out " + dir.Path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "wrote " + dir.Path("frame.png") + " (640x480 px, 10 robots, a ball) and " +
                       dir.Path("truth.csv") + "\n");
  EXPECT_EQ(ReadFile(dir.Path("truth.csv")), ReadFile(kGolden + "ssl-frame.truth.csv"));
  const camera::Image rendered = vision::ReadFrame(dir.Path("frame.png"));
  const camera::Image committed = vision::ReadFrame(kGolden + "ssl-frame.png");
  ASSERT_EQ(rendered.width_px, committed.width_px);
  ASSERT_EQ(rendered.height_px, committed.height_px);
  ASSERT_EQ(rendered.data.size(), committed.data.size());
  int max_diff = 0;
  size_t differ = 0;
  for (size_t i = 0; i < rendered.data.size(); ++i) {
    const int d = std::abs(rendered.data[i] - committed.data[i]);
    max_diff = std::max(max_diff, d);
    differ += d != 0;
  }
  EXPECT_LE(max_diff, 1);
  EXPECT_LT(static_cast<double>(differ), 0.001 * static_cast<double>(rendered.data.size()));
}

// (b) patlab detect on the committed frame finds every robot of the truth, with its team and
// ID, and nothing else. Tolerances against the true poses, derived:
//  - the scale on the robot tops is 800 px / 3860 mm = 0.207 px per mm (4.8 mm per px), so an
//    ID dot (20 mm) is a disc of r = 4.1 px, of which the thresholds keep the pixels at least
//    ~92% covered: r ~ 3.1 px, area A ~ 30 px^2 (ssl-frame.detector.toml, area_ratio_min);
//  - CMVision's blobs are binary: the centroid of the pixel centres in the region. Each of the
//    ~2 pi r = 19 boundary pixels is in or out where its true coverage is anywhere in (0, 1),
//    an error uniform in +-1/2 of weight ~r / A, half of them per axis: per blob and axis
//    sigma = sqrt(9.7) / sqrt(12) * 3.1 / 30 = 0.093 px = 0.45 mm. Anti-aliasing (1/16 per
//    pixel), the noise moving the threshold (3 levels against ~100 levels per px of edge) and
//    the projection of a disc's centroid (< 0.01 px) add far less;
//  - the pose's position is about the mean of the 5 patch positions: sigma = 0.45 / sqrt(5)
//    = 0.2 mm; its heading about sigma / sqrt(spread) (the Cramer-Rao bound, docs/architecture.md
//    "Numbers that matter"), the SSL pattern's sqrt(spread) being 129 mm: 0.0035 rad.
// We allow 4 sigma: 0.8 mm and 0.015 rad. Measured on the committed frame: at most 0.32 mm and
// 0.0061 rad (docs/render.md). A flipped axis, a wrong plane height or a wrong camera moves
// robots by tens of mm.
constexpr double kPositionToleranceMm = 0.8;
constexpr double kHeadingToleranceRad = 0.015;

// The detections of the robot of truth row `t` (same team and ID).
std::vector<Row> DetectionsOf(const Csv& detected, const Row& t) {
  std::vector<Row> found;
  for (const Row& d : detected.rows) {
    if (Cell(d, "team") == Cell(t, "team") && Cell(d, "id") == Cell(t, "id")) found.push_back(d);
  }
  return found;
}

// Detection `d` is the robot of truth row `t`, fully identified, within the tolerances.
void ExpectAtTruePose(const Row& d, const Row& t) {
  EXPECT_EQ(Cell(d, "pattern"), "ssl-standard");
  EXPECT_EQ(Cell(d, "status"), "ok");
  EXPECT_NEAR(Number(d, "x_mm"), Number(t, "x_mm"), kPositionToleranceMm);
  EXPECT_NEAR(Number(d, "y_mm"), Number(t, "y_mm"), kPositionToleranceMm);
  EXPECT_NEAR(WrapAngle(Number(d, "theta_rad") - Number(t, "theta_rad")), 0.0,
              kHeadingToleranceRad);
}

TEST(GoldenFrame, DetectFindsEveryRobotAtItsTruePose) {
  const CommandResult r = DetectGolden();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv detected = ParseCsv(r.out);
  const Csv truth = ParseCsv(ReadFile(kGolden + "ssl-frame.truth.csv"));
  ASSERT_EQ(truth.rows.size(), 10u);
  EXPECT_EQ(detected.rows.size(), truth.rows.size()) << r.out;  // none missed, no false positive
  for (const Row& t : truth.rows) {
    SCOPED_TRACE(Cell(t, "team") + " " + Cell(t, "id"));
    const std::vector<Row> found = DetectionsOf(detected, t);
    ASSERT_EQ(found.size(), 1u);
    ExpectAtTruePose(found.front(), t);
  }
}

// (b) ... and writes the committed expected CSV. The frame's pixels are fixed, so only the
// floating-point rounding of another machine can move a number, by far less than the CSV's last
// printed digit: one unit of it is allowed (0.01 mm, 0.0001 rad, 0.01 mm^2, 0.0001). Columns
// are matched by name, so columns added to the detect CSV later do not break this test; the
// frame column is compared by file name (the expected CSV was written from the repository root).
// Every cell of `want` (columns `header`) in `got`: numbers within one unit of the CSV's last
// digit, the frame by file name, the rest exactly.
void ExpectSameCells(const Row& got, const Row& want, const std::vector<std::string>& header) {
  const std::map<std::string, double> tolerance = {{"x_mm", 0.01},
                                                   {"y_mm", 0.01},
                                                   {"theta_rad", 1e-4},
                                                   {"residual_mm2", 0.01},
                                                   {"confidence", 1e-4}};
  for (const std::string& column : header) {
    const std::string w = Cell(want, column), g = Cell(got, column);
    if (column == "frame") {
      EXPECT_EQ(std::filesystem::path(g).filename(), std::filesystem::path(w).filename());
    } else if (tolerance.count(column)) {
      EXPECT_NEAR(std::stod(g), std::stod(w), tolerance.at(column)) << column;
    } else {
      EXPECT_EQ(g, w) << column;
    }
  }
}

TEST(GoldenFrame, DetectWritesTheExpectedDetections) {
  const CommandResult r = DetectGolden();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv detected = ParseCsv(r.out);
  const Csv expected = ParseCsv(ReadFile(kGolden + "ssl-frame.expected.csv"));
  ASSERT_FALSE(expected.rows.empty());
  ASSERT_EQ(detected.rows.size(), expected.rows.size()) << r.out;
  for (size_t i = 0; i < expected.rows.size(); ++i) {
    SCOPED_TRACE("detection " + std::to_string(i));
    ExpectSameCells(detected.rows[i], expected.rows[i], expected.header);
  }
}

TEST(RenderCli, BadInputIsExitTwoWithTheLine) {
  TempDir dir;
  const std::string scene =
      dir.Write("scene.toml", "calibration = \"" + kGolden +
                                  "ssl-frame.calibration.toml\"\n[render]\nseed = -1\n");
  CommandResult r = RunCommand(kPatlab + " render " + scene + " --out " + dir.Path("f.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab render: " + scene + ":3: seed is -1; expected an integer >= 0\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("f.png")));
  r = RunCommand(kPatlab + " render " + kGolden + "ssl-frame.toml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab render: missing --out DIR; expected the directory to write to\n");
  r = RunCommand(kPatlab + " render --out " + dir.Path("f.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab render: missing SCENE; expected 'patlab render SCENE -o DIR'\n");
}

TEST(RenderCli, HelpShowsAnExample) {
  const CommandResult r = RunCommand(kPatlab + " render --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("patlab render ssl-frame -o frame"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace patlab

#include "patlab/design/sheet_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "../expect_error.h"
#include "../frame_test_util.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/codebook_file.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/vision/frame_io.h"

namespace patlab::design {
namespace {

// A filled disc of colour rgb centred at (cx, cy) px.
void Disc(camera::Image* image, double cx, double cy, double r, std::array<uint8_t, 3> rgb) {
  for (int y = 0; y < image->height_px; ++y) {
    for (int x = 0; x < image->width_px; ++x) {
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r) continue;
      std::copy(rgb.begin(), rgb.end(), image->Row(y) + 3 * x);
    }
  }
}

constexpr std::array<uint8_t, 3> kBlue = {0, 0, 255}, kPink = {255, 0, 255}, kGreen = {0, 255, 0};

// Two cells: cell 0 a key with dots front-left (pink), front-right (green), back (green); cell 1
// the same without the back dot, so a different layout; cell 2 empty.
camera::Image TwoLayoutSheet() {
  camera::Image image = camera::Image::Rgb(600, 200);
  for (int x0 : {0, 200}) {
    Disc(&image, x0 + 100, 100, 25, kBlue);
    Disc(&image, x0 + 60, 40, 20, kPink);    // front-left: x = 60, y = 40 mm
    Disc(&image, x0 + 140, 40, 20, kGreen);  // front-right: x = 60, y = -40 mm
  }
  Disc(&image, 100, 165, 20, kGreen);  // back, cell 0 only: x = -65, y = 0 mm
  return image;
}

TEST(SheetImport, AbsentDotMakesAnotherLayout) {
  SheetImportOptions o;
  o.name = "two";
  const SheetImport sheet = ImportSheet(TwoLayoutSheet(), "two.png", o);
  EXPECT_EQ(sheet.columns, 3);
  ASSERT_EQ(sheet.cells.size(), 2u);
  ASSERT_EQ(sheet.slots.size(), 3u);
  EXPECT_NEAR(sheet.slots[0].x(), 60.0, 0.1);  // front-left first
  EXPECT_NEAR(sheet.slots[0].y(), 40.0, 0.1);
  EXPECT_NEAR(sheet.slots[1].y(), -40.0, 0.1);
  EXPECT_NEAR(sheet.slots[2].x(), -65.0, 0.1);
  ASSERT_EQ(sheet.layouts.size(), 2u);
  for (const ImportedLayout& l : sheet.layouts) {
    // The files read back through the project's own readers.
    const Pattern p = formats::ParsePattern(PatternFileText(l, sheet), l.pattern.name + ".toml");
    const detect::Codebook book = formats::ParseCodebook(CodebookFileText(l, sheet), "codebook", p,
                                                         detect::FindSymmetry(p, 10.0));
    ASSERT_EQ(book.entries.size(), 1u);
    if (p.size() == 4) {
      EXPECT_EQ(p.name, "two-1");
      EXPECT_EQ(book.entries[0].id, 0);
    } else {
      EXPECT_EQ(p.name, "two-2");
      EXPECT_EQ(book.entries[0].id, 1);
      EXPECT_EQ(p.size(), 3);
    }
  }
}

TEST(SheetImport, BadOptionsNameTheFlag) {
  SheetImportOptions o;
  o.cell_px = 0;
  EXPECT_INPUT_ERROR(ImportSheet(camera::Image::Rgb(400, 200), "x.png", o),
                     "--cell-px is 0; expected an integer in [20, 10000]");
  o = {};
  o.slot_tolerance_mm = -1.0;
  EXPECT_INPUT_ERROR(ImportSheet(camera::Image::Rgb(400, 200), "x.png", o),
                     "--slot-tolerance is -1; expected a finite number > 0 (mm)");
}

TEST(SheetImport, BadSheetsNameTheFile) {
  EXPECT_INPUT_ERROR(ImportSheet(camera::Image::Rgb(300, 200), "odd.png", {}),
                     "odd.png: the sheet is 300x200 px; expected a grid of 200 px cells");
  EXPECT_INPUT_ERROR(ImportSheet(camera::Image::Rgb(400, 200), "blank.png", {}),
                     "blank.png: no recognisable cells; expected 200 px cells each with a blue "
                     "key patch and coloured dots");
}

constexpr std::array<uint8_t, 3> kWhite = {255, 255, 255};

// A KIKS-like robot top centred at (cx, cy) px: a blue key of radius 25, a ring to radius 90 with
// the front quarter black (model angles -45..45 degrees) and three 90-degree sectors coloured
// left (45..135), back (135..225) and right (225..315).
void RingTop(camera::Image* image, double cx, double cy,
             const std::array<std::array<uint8_t, 3>, 3>& rgb) {
  for (int y = 0; y < image->height_px; ++y) {
    for (int x = 0; x < image->width_px; ++x) {
      const double dx = x - cx, dy = y - cy, r = std::hypot(dx, dy);
      if (r > 90.0 || r <= 25.0) continue;
      // Model angle: image up is +x, image left +y.
      double a = std::atan2(-dx, -dy) * 180.0 / std::numbers::pi;
      if (a < 0) a += 360.0;
      if (a < 45.0 || a >= 315.0) continue;
      const auto& c = rgb[static_cast<int>((a - 45.0) / 90.0)];
      std::copy(c.begin(), c.end(), image->Row(y) + 3 * x);
    }
  }
  Disc(image, cx, cy, 25, kBlue);
}

// Adjacent sectors of one colour merge into one region; the sectors come back by angle, each a
// disc at the sector's centroid: for an annular sector of radii r..R and angle alpha the centroid
// lies at 2/3 (R^3 - r^3) / (R^2 - r^2) sin(alpha/2) / (alpha/2) from the centre = 57.28 mm
// (r = 25, R = 90, alpha = 90 deg); the largest disc about it inside the sector reaches the
// nearer of key and rim: min(90 - 57.28, 57.28 - 25) - 0.5 = 31.78 mm.
TEST(SheetImport, RingSectorsAreSplitByAngle) {
  camera::Image image = camera::Image::Rgb(400, 200);
  RingTop(&image, 100, 100, {kGreen, kGreen, kWhite});  // left and back merge
  RingTop(&image, 300, 100, {kWhite, kGreen, kGreen});  // back and right merge
  SheetImportOptions o;
  o.name = "ring";
  const SheetImport sheet = ImportSheet(image, "ring.png", o);
  ASSERT_EQ(sheet.cells.size(), 2u);
  ASSERT_EQ(sheet.sector_bounds_deg.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(sheet.sector_bounds_deg[k], 45.0 + 90.0 * k, 1.0);
  const double alpha = std::numbers::pi / 2;
  const double d = 2.0 / 3.0 * (std::pow(90, 3) - std::pow(25, 3)) / (90 * 90 - 25 * 25) *
                   std::sin(alpha / 2) / (alpha / 2);
  ASSERT_EQ(sheet.slots.size(), 3u);
  EXPECT_NEAR(sheet.slots[0].y(), d, 0.5);   // left
  EXPECT_NEAR(sheet.slots[1].y(), -d, 0.5);  // right
  EXPECT_NEAR(sheet.slots[2].x(), -d, 0.5);  // back
  EXPECT_NEAR(sheet.slots[0].x(), 0.0, 0.5);
  ASSERT_EQ(sheet.layouts.size(), 1u);
  const ImportedLayout& l = sheet.layouts[0];
  const Pattern p = formats::ParsePattern(PatternFileText(l, sheet), "ring.toml");
  ASSERT_EQ(p.size(), 4);
  for (int i = 1; i < 4; ++i) {
    EXPECT_NEAR(p.patches[i].radius_mm, std::min(90.0 - d, d - 25.0) - 0.5, 1.0) << i;
  }
  // Geometry rejects every rotation (three quarters of a square): both colourings are IDs.
  const detect::Symmetry symmetry = detect::FindSymmetry(p, 10.0);
  EXPECT_EQ(symmetry.order(), 1);
  const detect::Codebook book =
      formats::ParseCodebook(CodebookFileText(l, sheet), "ring", p, symmetry);
  ASSERT_EQ(book.entries.size(), 2u);
  const auto colours = [&](int e) {
    std::vector<std::string> c;
    for (int k : book.entries[e].colour) c.push_back(book.colours[k]);
    return c;
  };
  EXPECT_EQ(colours(0), (std::vector<std::string>{"green", "white", "green"}));  // left right back
  EXPECT_EQ(colours(1), (std::vector<std::string>{"white", "green", "green"}));
}

TEST(SheetImport, RingOfOneColourAllRoundHasNoSectors) {
  camera::Image image = camera::Image::Rgb(200, 200);
  Disc(&image, 100, 100, 90, kGreen);
  Disc(&image, 100, 100, 25, kBlue);
  EXPECT_INPUT_ERROR(ImportSheet(image, "ring.png", {}),
                     "ring.png: ring sectors without a boundary; expected sectors of different "
                     "colours (or ring gaps) in at least one cell");
}

// The KIKS sheet: sectors, not dots; 12 cells, 8 distinct colourings of 3 sectors.
TEST(SheetImport, KiksSheetIsThreeSectors) {
  const std::string path = vision::testing::SharedFrames() + "/team-patterns/kiks.png";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "no shared sheet at " << path
                 << " (real sheets live in ../shared/frames, outside the repository)";
  }
  const SheetImport sheet = ImportSheet(vision::ReadFrame(path), path, {});
  EXPECT_EQ(sheet.cells.size(), 12u);
  EXPECT_EQ(sheet.slots.size(), 3u);
  ASSERT_EQ(sheet.layouts.size(), 1u);
  const ImportedLayout& l = sheet.layouts[0];
  EXPECT_EQ(l.codebook.entries.size(), 8u);  // 2^3 colourings, every one on the sheet
  EXPECT_EQ(l.dropped.size(), 4u);           // cells 8-11 repeat earlier cells
  const Pattern p = formats::ParsePattern(PatternFileText(l, sheet), "kiks.toml");
  EXPECT_EQ(detect::FindSymmetry(p, 10.0).order(), 1);
}

// The SSL standard sheet must come back as the shipped ssl-standard pattern and codebook.
TEST(SheetImport, StandardSheetIsTheShippedPattern) {
  const std::string path = vision::testing::SharedFrames() + "/ssl-standard-pattern-2010-16ids.png";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "no shared sheet at " << path
                 << " (real sheets live in ../shared/frames, outside the repository)";
  }
  SheetImportOptions o;
  o.name = "ssl-standard";
  const SheetImport sheet = ImportSheet(vision::ReadFrame(path), path, o);
  EXPECT_EQ(sheet.cells.size(), 16u);
  ASSERT_EQ(sheet.layouts.size(), 1u);
  const ImportedLayout& l = sheet.layouts[0];
  const std::string root = PATLAB_SOURCE_DIR;
  const Pattern shipped = formats::LoadPatternFile(root + "/patterns/ssl-standard.toml");
  const Pattern imported = formats::ParsePattern(PatternFileText(l, sheet), "imported.toml");
  ASSERT_EQ(imported.size(), shipped.size());
  for (int i = 0; i < shipped.size(); ++i) {
    EXPECT_EQ(imported.patches[i].role, shipped.patches[i].role) << i;
    EXPECT_NEAR(imported.patches[i].position_mm.x(), shipped.patches[i].position_mm.x(), 1.0) << i;
    EXPECT_NEAR(imported.patches[i].position_mm.y(), shipped.patches[i].position_mm.y(), 1.0) << i;
    EXPECT_NEAR(imported.patches[i].radius_mm, shipped.patches[i].radius_mm, 1.0) << i;
  }
  const detect::Symmetry symmetry = detect::FindSymmetry(shipped, 10.0);
  const detect::Codebook want =
      formats::LoadCodebookFile(root + "/patterns/ssl-standard.codebook.toml", shipped, symmetry);
  const detect::Codebook got =
      formats::ParseCodebook(CodebookFileText(l, sheet), "imported", shipped, symmetry);
  EXPECT_TRUE(l.dropped.empty());
  ASSERT_EQ(got.entries.size(), 16u);
  for (size_t e = 0; e < 16; ++e) {
    EXPECT_EQ(got.entries[e].id, want.entries[e].id);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(got.colours[got.entries[e].colour[k]], want.colours[want.entries[e].colour[k]])
          << "ID " << e << " slot " << k;
    }
  }
}

}  // namespace
}  // namespace patlab::design

#include "patlab/vision/sheet_import.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "../expect_error.h"
#include "patlab/detect/codebook.h"
#include "patlab/io/pattern_file.h"
#include "patlab/vision/frame_io.h"
#include "test_util.h"

namespace patlab::vision {
namespace {

// A filled disc of colour rgb centred at (cx, cy) px.
void Disc(Image* image, double cx, double cy, double r, std::array<uint8_t, 3> rgb) {
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
Image TwoLayoutSheet() {
  Image image = Image::Rgb(600, 200);
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
    const Pattern p = io::ParsePattern(PatternFileText(l, sheet), l.pattern.name + ".toml");
    const detect::Codebook book = detect::ParseCodebook(CodebookFileText(l, sheet), "codebook", p,
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
  EXPECT_INPUT_ERROR(ImportSheet(Image::Rgb(400, 200), "x.png", o),
                     "--cell-px is 0; expected an integer in [20, 10000]");
  o = {};
  o.slot_tolerance_mm = -1.0;
  EXPECT_INPUT_ERROR(ImportSheet(Image::Rgb(400, 200), "x.png", o),
                     "--slot-tolerance is -1; expected a finite number > 0 (mm)");
}

TEST(SheetImport, BadSheetsNameTheFile) {
  EXPECT_INPUT_ERROR(ImportSheet(Image::Rgb(300, 200), "odd.png", {}),
                     "odd.png: the sheet is 300x200 px; expected a grid of 200 px cells");
  EXPECT_INPUT_ERROR(ImportSheet(Image::Rgb(400, 200), "blank.png", {}),
                     "blank.png: no recognisable cells; expected 200 px cells each with a blue "
                     "key patch and coloured dots");
}

// The SSL standard sheet must come back as the shipped ssl-standard pattern and codebook.
TEST(SheetImport, StandardSheetIsTheShippedPattern) {
  const std::string path = testing::SharedFrames() + "/ssl-standard-pattern-2010-16ids.png";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "no shared sheet at " << path
                 << " (real sheets live in ../shared/frames, outside the repository)";
  }
  SheetImportOptions o;
  o.name = "ssl-standard";
  const SheetImport sheet = ImportSheet(ReadFrame(path), path, o);
  EXPECT_EQ(sheet.cells.size(), 16u);
  ASSERT_EQ(sheet.layouts.size(), 1u);
  const ImportedLayout& l = sheet.layouts[0];
  const std::string root = PATLAB_SOURCE_DIR;
  const Pattern shipped = io::LoadPatternFile(root + "/patterns/ssl-standard.toml");
  const Pattern imported = io::ParsePattern(PatternFileText(l, sheet), "imported.toml");
  ASSERT_EQ(imported.size(), shipped.size());
  for (int i = 0; i < shipped.size(); ++i) {
    EXPECT_EQ(imported.patches[i].role, shipped.patches[i].role) << i;
    EXPECT_NEAR(imported.patches[i].position_mm.x(), shipped.patches[i].position_mm.x(), 1.0) << i;
    EXPECT_NEAR(imported.patches[i].position_mm.y(), shipped.patches[i].position_mm.y(), 1.0) << i;
    EXPECT_NEAR(imported.patches[i].radius_mm, shipped.patches[i].radius_mm, 1.0) << i;
  }
  const detect::Symmetry symmetry = detect::FindSymmetry(shipped, 10.0);
  const detect::Codebook want =
      detect::LoadCodebookFile(root + "/patterns/ssl-standard.codebook.toml", shipped, symmetry);
  const detect::Codebook got =
      detect::ParseCodebook(CodebookFileText(l, sheet), "imported", shipped, symmetry);
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
}  // namespace patlab::vision

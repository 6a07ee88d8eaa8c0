#include "patlab/detect/codebook.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>
#include <set>

#include "../expect_error.h"
#include "patlab/core/error.h"
#include "patlab/formats/codebook_file.h"
#include "test_util.h"

namespace patlab::detect {
namespace {

using testing::LoadPattern;

TEST(Symmetry, GroupOrdersOfThePapersPatterns) {
  EXPECT_EQ(FindSymmetry(LoadPattern("simple"), 10.0).order(), 1);
  EXPECT_EQ(FindSymmetry(LoadPattern("linear"), 10.0).order(), 2);
  EXPECT_EQ(FindSymmetry(LoadPattern("triangle"), 10.0).order(), 3);
  EXPECT_EQ(FindSymmetry(LoadPattern("butterfly"), 10.0).order(), 1);
  EXPECT_EQ(FindSymmetry(LoadPattern("ssl-standard"), 10.0).order(), 1);
}

TEST(Symmetry, LinearHalfTurnAndTriangleThirdTurns) {
  const Symmetry linear = FindSymmetry(LoadPattern("linear"), 10.0);
  EXPECT_THAT(linear.shifts, ::testing::ElementsAre(0, 1));
  EXPECT_NEAR(std::abs(linear.angles_rad[1]), std::numbers::pi, 1e-9);
  const Symmetry triangle = FindSymmetry(LoadPattern("triangle"), 10.0);
  EXPECT_THAT(triangle.shifts, ::testing::ElementsAre(0, 1, 2));
  EXPECT_NEAR(triangle.angles_rad[1], 2.0 * std::numbers::pi / 3.0, 1e-9);
  EXPECT_NEAR(triangle.angles_rad[2], -2.0 * std::numbers::pi / 3.0, 1e-9);
}

// The SSL pattern's dots sit at +-57.4 and +-147.4 degrees on a 65 mm circle: a quarter turn moves
// two of them 2 * 65 * sin(12.6 deg / 2)... by about 28 mm from the nearest dot (hand computed:
// |(35, -54.772) rotated by 90 deg - (35, 54.772)| = |(54.772, 35) - (35, 54.772)| = 27.96 mm;
// the least-squares quarter turn spreads that over all four). Below that tolerance the pattern is
// asymmetric; far above it, it has the symmetry of a square.
TEST(Symmetry, ButterflyBecomesFourFoldWithALooseTolerance) {
  const Pattern ssl = LoadPattern("ssl-standard");
  EXPECT_EQ(FindSymmetry(ssl, 10.0).order(), 1);
  EXPECT_EQ(FindSymmetry(ssl, 27.0).order(), 1);
  EXPECT_EQ(FindSymmetry(ssl, 28.0).order(), 4);
}

TEST(Symmetry, CircularOrderIsByAngleAboutTheKey) {
  // ssl-standard patches: 1 FL (+57.4), 2 FR (-57.4), 3 BL (+147.4), 4 BR (-147.4).
  EXPECT_THAT(FindSymmetry(LoadPattern("ssl-standard"), 10.0).circular_order,
              ::testing::ElementsAre(4, 2, 1, 3));
}

// Table II with this project's counting rule, hand computed:
//   simple   n               (one slot, no symmetry)
//   linear   (n^2 - n) / 2   (half turn: colourings with two equal colours are ambiguous)
//   triangle (n^3 - n) / 3   (third turns: monochrome colourings are ambiguous)
//   butterfly n^4            (geometry fixes the rotation)
TEST(CountIds, TableTwo) {
  const Pattern simple = LoadPattern("simple"), linear = LoadPattern("linear"),
                triangle = LoadPattern("triangle"), butterfly = LoadPattern("butterfly");
  const int expected[4][3] = {{2, 3, 4}, {1, 3, 6}, {2, 8, 20}, {16, 81, 256}};
  const Pattern* patterns[4] = {&simple, &linear, &triangle, &butterfly};
  for (int p = 0; p < 4; ++p) {
    const Symmetry symmetry = FindSymmetry(*patterns[p], 10.0);
    for (int n = 2; n <= 4; ++n) {
      EXPECT_EQ(CountIds(*patterns[p], symmetry, n), static_cast<uint64_t>(expected[p][n - 2]))
          << patterns[p]->name << " n=" << n;
    }
  }
}

TEST(CountIds, SingleColourHasIdsOnlyWithoutSymmetry) {
  EXPECT_EQ(CountIds(LoadPattern("simple"), FindSymmetry(LoadPattern("simple"), 10), 1), 1u);
  EXPECT_EQ(CountIds(LoadPattern("linear"), FindSymmetry(LoadPattern("linear"), 10), 1), 0u);
  EXPECT_EQ(CountIds(LoadPattern("triangle"), FindSymmetry(LoadPattern("triangle"), 10), 1), 0u);
}

TEST(CountIds, ButterflyWithSquareSymmetry) {
  // Four-fold: (n^4 - n^2) / 4 colourings fix the rotation (Moebius: mu(2) removes the n^2
  // colourings fixed by the half turn, which include the n fixed by the quarter turns).
  const Pattern ssl = LoadPattern("ssl-standard");
  const Symmetry loose = FindSymmetry(ssl, 30.0);
  EXPECT_EQ(CountIds(ssl, loose, 2), 3u);
  EXPECT_EQ(CountIds(ssl, loose, 3), 18u);
}

TEST(GenerateCodebook, EnumerationAgreesWithBurnside) {
  for (const char* name : {"simple", "linear", "triangle", "butterfly"}) {
    const Pattern pattern = LoadPattern(name);
    for (double tolerance : {10.0, 30.0}) {
      const Symmetry symmetry = FindSymmetry(pattern, tolerance);
      for (int n = 1; n <= 5; ++n) {
        std::vector<std::string> colours;
        for (int c = 0; c < n; ++c) colours.push_back(std::string(1, static_cast<char>('A' + c)));
        const Codebook book = GenerateCodebook(pattern, symmetry, colours);
        EXPECT_EQ(book.entries.size(), CountIds(pattern, symmetry, n)) << name << " n=" << n;
      }
    }
  }
}

TEST(GenerateCodebook, LinearListsOneColouringPerClass) {
  const Pattern linear = LoadPattern("linear");
  const Codebook book =
      GenerateCodebook(linear, FindSymmetry(linear, 10.0), {"pink", "green", "cyan"});
  ASSERT_EQ(book.entries.size(), 3u);
  EXPECT_THAT(book.entries[0].colour, ::testing::ElementsAre(0, 1));
  EXPECT_THAT(book.entries[1].colour, ::testing::ElementsAre(0, 2));
  EXPECT_THAT(book.entries[2].colour, ::testing::ElementsAre(1, 2));
  EXPECT_EQ(book.entries[2].id, 2);
}

TEST(GenerateCodebook, TriangleKeepsBothCyclicOrdersOfThreeColours) {
  const Pattern triangle = LoadPattern("triangle");
  const Codebook book =
      GenerateCodebook(triangle, FindSymmetry(triangle, 10.0), {"pink", "green", "cyan"});
  std::set<std::vector<int>> colourings;
  for (const CodebookEntry& e : book.entries) colourings.insert(e.colour);
  EXPECT_TRUE(colourings.count({0, 1, 2}));
  EXPECT_TRUE(colourings.count({0, 2, 1}));
  EXPECT_FALSE(colourings.count({1, 2, 0}));  // {0, 1, 2} rotated
  EXPECT_FALSE(colourings.count({1, 1, 1}));  // monochrome: ambiguous
}

TEST(StabilisingShift, NamesTheRotationThatKeepsAColouring) {
  const Pattern linear = LoadPattern("linear");
  const Symmetry symmetry = FindSymmetry(linear, 10.0);
  EXPECT_EQ(StabilisingShift(linear, symmetry, {1, 1}), 1);
  EXPECT_EQ(StabilisingShift(linear, symmetry, {0, 1}), 0);
}

TEST(Symmetry, FixedColourBreaksTheSymmetryForIdentification) {
  // Linear with a red front marker and one ID slot behind: geometry has the half turn, but it
  // maps the red patch onto the ID slot, so colours fix the rotation: every colour is an ID.
  Pattern pattern = LoadPattern("linear");
  pattern.patches[1].role = PatchRole::kFixed;
  pattern.patches[1].colour = "red";
  const Symmetry symmetry = FindSymmetry(pattern, 10.0);
  EXPECT_EQ(symmetry.order(), 2);
  EXPECT_EQ(symmetry.effective_order(), 1);
  EXPECT_EQ(CountIds(pattern, symmetry, 3), 3u);
}

TEST(CodebookFile, SslStandardHasTheSixteenReadmeIds) {
  const Pattern ssl = LoadPattern("ssl-standard");
  const Codebook book = formats::LoadCodebookFile(
      std::string(PATLAB_SOURCE_DIR) + "/patterns/ssl-standard.codebook.toml", ssl,
      FindSymmetry(ssl, 10.0));
  ASSERT_EQ(book.entries.size(), 16u);
  EXPECT_THAT(book.colours, ::testing::ElementsAre("pink", "green"));
  // frames/README.md: 0 PPGP, 8 GGGG, 9 PPPP, 13 GPPP (P = 0, G = 1).
  EXPECT_THAT(book.entries[0].colour, ::testing::ElementsAre(0, 0, 1, 0));
  EXPECT_THAT(book.entries[8].colour, ::testing::ElementsAre(1, 1, 1, 1));
  EXPECT_THAT(book.entries[9].colour, ::testing::ElementsAre(0, 0, 0, 0));
  EXPECT_THAT(book.entries[13].colour, ::testing::ElementsAre(1, 0, 0, 0));
  std::set<std::vector<int>> distinct;
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(book.entries[i].id, i);
    distinct.insert(book.entries[i].colour);
  }
  EXPECT_EQ(distinct.size(), 16u);
}

void ExpectCodebookError(const std::string& pattern_name, const std::string& text,
                         const std::string& message) {
  const Pattern pattern = LoadPattern(pattern_name);
  EXPECT_INPUT_ERROR(
      formats::ParseCodebook(text, "book.toml", pattern, FindSymmetry(pattern, 10.0)), message);
}

TEST(CodebookFile, BadFilesGiveTheirMessages) {
  ExpectCodebookError("linear",
                      "pattern = \"linear\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\n"
                      "slots = [\"pink\", \"pink\"]\n",
                      "book.toml:5: ID 0 is ambiguous: rotating linear by 180 degrees maps it "
                      "onto itself; expected colours that fix the rotation");
  ExpectCodebookError(
      "linear",
      "pattern = \"linear\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\n"
      "slots = [\"pink\", \"green\"]\n[[id]]\nid = 1\nslots = [\"green\", \"pink\"]\n",
      "book.toml:8: ID 1 is ID 0 rotated by 180 degrees; expected colourings that "
      "differ up to the pattern's symmetry");
  ExpectCodebookError(
      "ssl-standard",
      "pattern = \"ssl-standard\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 0\n"
      "slots = [\"pink\", \"green\"]\n",
      "book.toml:5: ID 0 has 2 colours; expected 4 (one per ID slot of "
      "ssl-standard)");
  ExpectCodebookError("simple",
                      "pattern = \"simple\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 3\n"
                      "slots = [\"red\"]\n",
                      "book.toml:5: ID 3 has colour \"red\"; expected one of: pink, green");
  ExpectCodebookError("simple", "pattern = \"linear\"\ncolours = [\"pink\"]\n",
                      "book.toml:1: pattern is \"linear\"; expected \"simple\" (the pattern this "
                      "codebook is loaded for)");
  ExpectCodebookError("simple",
                      "pattern = \"simple\"\ncolours = [\"pink\", \"green\"]\n[[id]]\nid = 1\n"
                      "slots = [\"pink\"]\n[[id]]\nid = 1\nslots = [\"green\"]\n",
                      "book.toml:7: id 1 appears twice (first at line 3); expected distinct IDs");
  ExpectCodebookError("simple", "pattern = \"simple\"\ncolours = [\"pink\"]\n",
                      "book.toml:1: no IDs; expected [[id]] tables with id = <integer> and slots = "
                      "[<colour per ID slot>]");
}

}  // namespace
}  // namespace patlab::detect

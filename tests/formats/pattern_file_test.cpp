#include "patlab/formats/pattern_file.h"

#include <gtest/gtest.h>

#include <numbers>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/core/error.h"

namespace patlab::formats {
namespace {

constexpr const char* kKey = "[[patch]]\nrole = \"key\"\nx = 0.0\ny = 0.0\nradius = 25.0\n";

std::string Patch(const std::string& x, const std::string& y, const std::string& extra = "") {
  return "[[patch]]\nrole = \"id\"\nx = " + x + "\ny = " + y + "\nradius = 20.0\n" + extra;
}

TEST(PatternFile, ShippedPatternsLoadWithTheDocumentedGeometry) {
  const Pattern ssl = testing::ShippedPattern("ssl-standard");
  ASSERT_EQ(ssl.size(), 5);
  EXPECT_EQ(ssl.key_index, 0);
  EXPECT_EQ(ssl.patches[0].radius_mm, 25.0);
  EXPECT_EQ(ssl.patches[1].position_mm, Vec2(35.0, 54.772));
  EXPECT_EQ(ssl.patches[4].position_mm, Vec2(-54.772, -35.0));
  for (int i = 1; i < 5; ++i) EXPECT_NEAR(ssl.patches[i].position_mm.norm(), 65.0, 1e-3);
  EXPECT_EQ(ssl.orientation_pairs.size(), 6u);  // all pairs of the four non-key patches

  const Pattern simple = testing::ShippedPattern("simple");
  ASSERT_EQ(simple.orientation_pairs.size(), 1u);  // key -> the other patch
  EXPECT_EQ(simple.orientation_pairs[0], (OrientationPair{0, 1}));
  const Pattern linear = testing::ShippedPattern("linear");
  ASSERT_EQ(linear.orientation_pairs.size(), 1u);  // the long pair between the outer patches
  EXPECT_EQ(linear.orientation_pairs[0], (OrientationPair{1, 2}));
  const Pattern triangle = testing::ShippedPattern("triangle");
  EXPECT_EQ(triangle.orientation_pairs.size(), 3u);  // the three triangle edges
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(triangle.patches[i].position_mm.norm(), 65.0, 1e-12);
}

TEST(PatternFile, ExplicitOrientationPairsAreKept) {
  const Pattern p =
      ParsePattern(std::string("name = \"t\"\norientation_pairs = [[1, 2], [0, 2]]\n") + kKey +
                       Patch("65", "0") + Patch("-65", "0"),
                   "p.toml");
  ASSERT_EQ(p.orientation_pairs.size(), 2u);
  EXPECT_EQ(p.orientation_pairs[1], (OrientationPair{0, 2}));
}

struct BadCase {
  const char* what;
  std::string text;
  std::string message;
};

TEST(PatternFile, BadFilesAreRejectedWithFileLineAndWhatWasExpected) {
  const std::string head = "name = \"t\"\n";
  const std::vector<BadCase> cases = {
      {"syntax", head + "x = = 1\n",
       "p.toml:2: TOML syntax error: Error while parsing value: could not determine value type"},
      {"no key", head + Patch("0", "0") + Patch("65", "0"),
       "p.toml:2: no key patch; expected exactly one patch with role = \"key\""},
      {"two keys", head + kKey + "[[patch]]\nrole = \"key\"\nx = 65.0\ny = 0.0\nradius = 25.0\n",
       "p.toml:8: second key patch ([[patch]] 1; the first is [[patch]] 0); expected exactly one "
       "patch with role = \"key\""},
      {"coincident", head + kKey + Patch("65", "0") + Patch("65", "0"),
       "p.toml:12: [[patch]] 2 coincides with [[patch]] 1 at (65, 0); expected distinct patch "
       "positions"},
      {"overlapping", head + kKey + Patch("30", "0"),
       "p.toml:7: [[patch]] 1 overlaps [[patch]] 0: centres 30 mm apart, radii 20 + 25 mm; "
       "expected centre distance >= sum of radii"},
      {"pair out of range", head + "orientation_pairs = [[1, 5]]\n" + kKey + Patch("65", "0"),
       "p.toml:2: orientation pair 0 [1, 5]: patch index 5 out of range; expected 0..1"},
      {"pair of zero length", head + "orientation_pairs = [[1, 1]]\n" + kKey + Patch("65", "0"),
       "p.toml:2: orientation pair 0 [1, 1] has zero length; expected two different patches"},
      {"pair not integers", head + "orientation_pairs = [[1, \"a\"]]\n" + kKey + Patch("65", "0"),
       "p.toml:2: orientation pair 0 is not two integers; expected an array of [from, to] patch "
       "index pairs, e.g. [[1, 2], [3, 4]]"},
      {"orientation undefined: one patch", head + kKey,
       "p.toml:2: pattern has 1 patch; expected at least 2 (orientation needs two distinct patch "
       "positions)"},
      {"no patches", head,
       "p.toml:1: no patches; expected at least 2 [[patch]] tables (orientation needs two distinct "
       "patch positions)"},
      {"non-finite", head + kKey + Patch("nan", "0"),
       "p.toml:9: x in [[patch]] 1 is nan; expected a finite number"},
      {"infinite", head + kKey + Patch("65", "-inf"),
       "p.toml:10: y in [[patch]] 1 is -inf; expected a finite number"},
      {"unknown key (typo)", head + kKey + Patch("65", "0", "radus = 3\n"),
       "p.toml:12: unknown key 'radus' in [[patch]] 1; expected one of: x, y, radius, role, "
       "colour, shape, size, angle_deg"},
      {"unknown top-level key", head + "patches = 3\n" + kKey,
       "p.toml:2: unknown key 'patches'; expected one of: name, description, orientation_pairs, "
       "patch"},
      {"wrong type", head + kKey + Patch("\"65\"", "0"),
       "p.toml:9: x in [[patch]] 1 is a string; expected a number"},
      {"bad role", head + kKey + "[[patch]]\nrole = \"slot\"\nx = 65.0\ny = 0.0\nradius = 20.0\n",
       "p.toml:8: role in [[patch]] 1 is \"slot\"; expected \"key\", \"id\" or \"fixed\""},
      {"negative radius",
       head + kKey + "[[patch]]\nrole = \"id\"\nx = 65.0\ny = 0.0\nradius = -2\n",
       "p.toml:11: radius in [[patch]] 1 is -2; expected a positive number (mm)"},
      {"missing name", std::string(kKey) + Patch("65", "0"),
       "p.toml:1: missing name; expected a string"},
      {"fixed without colour",
       head + kKey + "[[patch]]\nrole = \"fixed\"\nx = 65.0\ny = 0.0\nradius = 20.0\n",
       "p.toml:8: [[patch]] 1 has role \"fixed\" but no colour; expected colour = \"<name>\""},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_INPUT_ERROR(ParsePattern(c.text, "p.toml"), c.message);
  }
}

constexpr const char* kRectKey =
    "[[patch]]\nrole = \"key\"\nshape = \"rectangle\"\nx = 0.0\ny = 18.0\nsize = [70, 32]\n";

std::string RectId(const std::string& y, const std::string& extra = "") {
  return "[[patch]]\nrole = \"id\"\nshape = \"rectangle\"\nx = 0.0\ny = " + y +
         "\nsize = [70, 32]\n" + extra;
}

TEST(PatternFile, RectanglesLoadWithAreaAndEqualAreaRadius) {
  const Pattern vss = testing::ShippedPattern("vss-two-rectangles");
  ASSERT_EQ(vss.size(), 2);
  for (const patlab::Patch& p : vss.patches) {
    EXPECT_EQ(p.shape, PatchShape::kRectangle);
    EXPECT_EQ(p.size_mm, Vec2(70.0, 32.0));
    EXPECT_DOUBLE_EQ(p.Area(), 2240.0);
  }
  EXPECT_EQ(vss.patches[0].position_mm, Vec2(0.0, 18.0));
  EXPECT_EQ(vss.patches[1].position_mm, Vec2(0.0, -18.0));
  EXPECT_EQ(vss.orientation_pairs.size(), 1u);
  // A rotated rectangle next to a disc.
  const Pattern p = ParsePattern(std::string("name = \"t\"\n") + kKey +
                                     "[[patch]]\nrole = \"id\"\nshape = \"rectangle\"\nx = 60\n"
                                     "y = 0\nsize = [40, 10]\nangle_deg = 90\n",
                                 "p.toml");
  EXPECT_NEAR(p.patches[1].angle_rad, std::numbers::pi / 2, 1e-15);
  EXPECT_EQ(p.patches[0].shape, PatchShape::kDisc);
}

TEST(PatternFile, BadRectanglesAreRejectedWithFileLineAndWhatWasExpected) {
  const std::string head = "name = \"t\"\n";
  const std::vector<BadCase> cases = {
      {"unknown shape",
       head + kKey + "[[patch]]\nrole = \"id\"\nshape = \"square\"\nx = 65\ny = 0\nradius = 5\n",
       "p.toml:9: shape in [[patch]] 1 is \"square\"; expected \"disc\" or \"rectangle\""},
      {"rectangle without size",
       head + kKey + "[[patch]]\nrole = \"id\"\nshape = \"rectangle\"\nx = 65\ny = 0\n",
       "p.toml:7: [[patch]] 1 is a rectangle without size; expected size = [sx, sy] (mm, the sides "
       "along the rectangle's x and y)"},
      {"rectangle with radius", head + kRectKey + RectId("-18", "radius = 3\n"),
       "p.toml:14: [[patch]] 1 is a rectangle with a radius; expected size = [sx, sy] (mm) and no "
       "radius"},
      {"size not two numbers",
       head + kRectKey +
           "[[patch]]\nrole = \"id\"\nshape = \"rectangle\"\nx = 0\ny = -18\nsize = [70]\n",
       "p.toml:13: [[patch]] 1 is a rectangle whose size is not two numbers; expected size = [sx, "
       "sy] (mm, the sides along the rectangle's x and y)"},
      {"size not positive",
       head + kRectKey +
           "[[patch]]\nrole = \"id\"\nshape = \"rectangle\"\nx = 0\ny = -18\nsize = [70, 0]\n",
       "p.toml:13: size[1] in [[patch]] 1 is 0; expected a positive number (mm)"},
      {"disc with size", head + kKey + Patch("65", "0", "size = [3, 4]\n"),
       "p.toml:12: [[patch]] 1 is a disc with size; expected radius only, or shape = "
       "\"rectangle\""},
      {"angle out of range", head + kRectKey + RectId("-18", "angle_deg = 400\n"),
       "p.toml:14: angle_deg in [[patch]] 1 is 400; expected an angle in [-360, 360] (degrees)"},
      {"rectangles overlap", head + kRectKey + RectId("-12"),
       "p.toml:8: [[patch]] 1 (rectangle) overlaps [[patch]] 0 (rectangle) by 2 mm; expected "
       "patches that do not overlap"},
      {"rectangle overlaps disc", head + kKey + RectId("40"),
       "p.toml:7: [[patch]] 1 (rectangle) overlaps [[patch]] 0 (disc) by 1 mm; expected patches "
       "that do not overlap"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_INPUT_ERROR(ParsePattern(c.text, "p.toml"), c.message);
  }
}

TEST(PatternFile, MissingFileIsAnInputError) {
  EXPECT_INPUT_ERROR(LoadPatternFile("/nonexistent/p.toml"),
                     "/nonexistent/p.toml: cannot open file; expected a readable TOML file");
}

}  // namespace
}  // namespace patlab::formats

// A name longer than the file system takes (fuzzing found std::filesystem_error escaping here) is
// an InputError that says so.
TEST(PatternFile, NameTheFileSystemRefusesIsAnInputError) {
  const std::string name(300, 'a');
  EXPECT_INPUT_ERROR(patlab::formats::ResolvePatternPath(name, "patterns"),
                     name +
                         ": File name too long; expected a path whose every component is at "
                         "most 255 bytes");
}

namespace patlab::formats {
namespace {

// A fixed patch's colour is read as the vocabulary's name (core/colour_names.h); a misspelt one
// is an error with a did-you-mean.
TEST(PatternFile, FixedColourNamesResolveThroughTheVocabulary) {
  const std::string fixed = "[[patch]]\nrole = \"fixed\"\nx = 65.0\ny = 0.0\nradius = 20.0\n";
  const Pattern p = ParsePattern(std::string("name = \"t\"\n") + kKey + fixed +
                                     "colour = \"Light_Blue\"\n" + Patch("-65", "0"),
                                 "p.toml");
  EXPECT_EQ(p.patches[1].colour, "light-blue");
  EXPECT_INPUT_ERROR(ParsePattern(std::string("name = \"t\"\n") + kKey + fixed +
                                      "colour = \"oragne\"\n" + Patch("-65", "0"),
                                  "p.toml"),
                     "p.toml:12: unknown colour 'oragne'; expected a colour of "
                     "settings/colours.toml (did you mean 'orange'?)");
}

}  // namespace
}  // namespace patlab::formats

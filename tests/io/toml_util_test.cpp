// Tests of the TOML helpers (src/patlab/io/toml_util.h).
#include "patlab/io/toml_util.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/core/format.h"

namespace patlab::io {
namespace {

constexpr const char* kText =
    "runs = 3\n"           // line 1
    "[camera]\n"           // line 2
    "height_mm = 2500\n"   // line 3
    "[noise]\n"            // line 4
    "pixel_sigma = -1\n";  // line 5

TEST(FieldLoc, FindsTheKeyOrTheDeepestTableOfItsPath) {
  const toml::table root = ParseTomlText(kText, "e.toml");
  EXPECT_EQ(FieldLoc(root, "e.toml", "runs").ToString(), "e.toml:1");
  EXPECT_EQ(FieldLoc(root, "e.toml", "camera.height_mm").ToString(), "e.toml:3");
  EXPECT_EQ(FieldLoc(root, "e.toml", "noise.pixel_sigma").ToString(), "e.toml:5");
  // A key the file does not set: its table's line; a table the file lacks: the file's root.
  EXPECT_EQ(FieldLoc(root, "e.toml", "camera.focal_length_px").ToString(), "e.toml:2");
  EXPECT_EQ(FieldLoc(root, "e.toml", "render.supersampling").ToString(),
            LocOf("e.toml", root).ToString());
  // A scalar where a table is expected: the scalar's line.
  EXPECT_EQ(FieldLoc(root, "e.toml", "runs.x").ToString(), "e.toml:1");
}

TEST(FieldLoc, ThrowFirstProblemAtPlacesTheMessage) {
  const toml::table root = ParseTomlText(kText, "e.toml");
  ThrowFirstProblemAt(root, "e.toml", {});
  EXPECT_INPUT_ERROR(
      ThrowFirstProblemAt(
          root, "e.toml",
          {{"noise.pixel_sigma", "noise.pixel_sigma is -1; expected >= 0"}, {"runs", "second"}}),
      "e.toml:5: noise.pixel_sigma is -1; expected >= 0");
}

}  // namespace
}  // namespace patlab::io

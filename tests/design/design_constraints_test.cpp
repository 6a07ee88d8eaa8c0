// The constraints file of patlab design (design/design.h ParseDesignConstraints): every key read,
// absent keys kept, and bad values at their file:line with what was expected.
#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/design/design.h"

namespace patlab::design {
namespace {

TEST(DesignConstraints, EveryKeyIsRead) {
  const DesignOptions o = ParseDesignConstraints(R"(name = "ssl-top"
outer_diameter_mm = 178
rim_gap_mm = 2
key_radius_mm = 24
id_patches = 3
id_radii_mm = [18, 19, 20]
min_gap_mm = 12
palette = 3
tolerance_mm = 8
objective = "rotation_onset"
symmetry = "mirror"
min_ids = 20
min_rotation_onset_mm = 1.5
max_angle_crlb_mrad_per_mm = 9.5
max_position_crlb_per_mm = 0.6
starts = 7
max_evaluations = 500
seed = 42
)",
                                                 "c.toml", {});
  EXPECT_EQ(o.name, "ssl-top");
  EXPECT_EQ(o.outer_diameter_mm, 178);
  EXPECT_EQ(o.rim_gap_mm, 2);
  EXPECT_EQ(o.key_radius_mm, 24);
  EXPECT_EQ(o.id_patches, 3);
  EXPECT_EQ(o.id_radii_mm, (std::vector<double>{18, 19, 20}));
  EXPECT_EQ(o.min_gap_mm, 12);
  EXPECT_EQ(o.palette, 3);
  EXPECT_EQ(o.tolerance_mm, 8);
  EXPECT_EQ(o.objective, DesignObjective::kRotationOnset);
  EXPECT_EQ(o.symmetry, DesignSymmetry::kMirror);
  EXPECT_EQ(o.min_ids, 20);
  EXPECT_EQ(o.min_rotation_onset_mm, 1.5);
  EXPECT_EQ(o.max_angle_crlb_mrad_per_mm, 9.5);
  EXPECT_EQ(o.max_position_crlb_per_mm, 0.6);
  EXPECT_EQ(o.starts, 7);
  EXPECT_EQ(o.max_evaluations, 500);
  EXPECT_EQ(o.seed, 42u);
}

TEST(DesignConstraints, AbsentKeysKeepTheDefaults) {
  DesignOptions defaults;
  defaults.starts = 3;
  const DesignOptions o = ParseDesignConstraints("id_radii_mm = 18\n", "c.toml", defaults);
  EXPECT_EQ(o.id_radii_mm, std::vector<double>{18});
  EXPECT_EQ(o.starts, 3);
  EXPECT_EQ(o.outer_diameter_mm, 180);
  EXPECT_EQ(o.symmetry, DesignSymmetry::kNone);
}

TEST(DesignConstraints, BadValuesNameTheLine) {
  EXPECT_INPUT_ERROR(ParseDesignConstraints("palette = 2\nid_patches = 0\n", "c.toml", {}),
                     "c.toml:2: id_patches is 0; expected an integer in [1, 11]");
  EXPECT_INPUT_ERROR(ParseDesignConstraints("\nid_radii_mm = 30\n", "c.toml", {}),
                     "c.toml:2: id_radii_mm is 30; expected at most (outer_diameter_mm / 2 - "
                     "rim_gap_mm - key_radius_mm - min_gap_mm) / 2 = 22.5 (an ID patch must fit "
                     "between the key patch and the rim)");
  EXPECT_INPUT_ERROR(ParseDesignConstraints("symmetry = \"radial\"\n", "c.toml", {}),
                     "c.toml:1: symmetry is \"radial\"; expected \"none\", \"mirror\" or "
                     "\"cyclic\"");
  EXPECT_INPUT_ERROR(ParseDesignConstraints("id_radii_mm = [20, \"big\"]\n", "c.toml", {}),
                     "c.toml:1: id_radii_mm holds a string; expected an array of numbers (mm), "
                     "one per ID patch");
  EXPECT_INPUT_ERROR(ParseDesignConstraints("min_gap_mm = \"wide\"\n", "c.toml", {}),
                     "c.toml:1: min_gap_mm is a string; expected a number");
  EXPECT_INPUT_ERROR(ParseDesignConstraints("seed = -1\n", "c.toml", {}),
                     "c.toml:1: seed is -1; expected an integer >= 0");
}

}  // namespace
}  // namespace patlab::design

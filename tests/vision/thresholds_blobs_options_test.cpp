// The colour fit's options by name (vision/thresholds_blobs.h SetBlobThresholdsOption), behind
// `patlab setup --colour-option NAME=VALUE`: each name sets its own field and no other, the
// fields setup sets from the calibration are not names, and a wrong name or value says what is
// expected.
#include <gtest/gtest.h>

#include <string>

#include "patlab/core/error.h"
#include "patlab/vision/thresholds_blobs.h"

namespace patlab::vision {
namespace {

// Every field, read back as a number (integer fields widened), in declaration order.
std::vector<double> Fields(const BlobThresholdsOptions& o) {
  return {o.min_blob_area_px,
          o.max_blob_area_px,
          o.min_blob_sigma_px,
          double(o.light_cell_px),
          o.max_light_gain,
          o.standout_delta_e,
          o.segment_k,
          o.cluster_distance,
          o.lightness_weight,
          o.hue_spread_deg,
          o.lightness_spread,
          o.chroma_spread,
          o.achromatic_chroma,
          o.max_name_cost,
          o.lower_percentile,
          o.upper_percentile,
          o.lighting_min_gain,
          o.lighting_max_gain,
          double(o.margin_levels),
          o.negative_weight};
}

TEST(BlobThresholdsOptionNames, EachNameSetsItsOwnFieldAndNoOther) {
  const std::vector<std::string> names = BlobThresholdsOptionNames();
  const std::vector<double> defaults = Fields(BlobThresholdsOptions{});
  // 20 fields, 17 names: the blob area range and spread are setup's, from the calibration.
  ASSERT_EQ(defaults.size(), 20u);
  ASSERT_EQ(names.size(), 17u);
  std::vector<int> set_by(defaults.size(), 0);
  for (const std::string& name : names) {
    BlobThresholdsOptions o;
    SetBlobThresholdsOption(name, 7.0, &o);
    const std::vector<double> after = Fields(o);
    int changed = 0;
    for (size_t i = 0; i < after.size(); ++i) {
      if (after[i] != defaults[i]) {
        EXPECT_EQ(after[i], 7.0) << name;
        ++set_by[i];
        ++changed;
      }
    }
    EXPECT_EQ(changed, 1) << name << " (7 is no field's default)";
  }
  EXPECT_EQ(set_by, std::vector<int>({0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1}));
  BlobThresholdsOptions o;
  SetBlobThresholdsOption("segment_k", 90.0, &o);
  SetBlobThresholdsOption("margin_levels", 5.0, &o);
  EXPECT_EQ(o.segment_k, 90.0);
  EXPECT_EQ(o.margin_levels, 5);
}

TEST(BlobThresholdsOptionNames, AWrongNameOrValueSaysWhatIsExpected) {
  BlobThresholdsOptions o;
  try {
    SetBlobThresholdsOption("min_blob_area_px", 10.0, &o);
    FAIL() << "setup's own field was settable";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("unknown colour option 'min_blob_area_px'; expected one "
                                          "of light_cell_px, max_light_gain, ",
                                          0),
              0u)
        << e.what();
  }
  try {
    SetBlobThresholdsOption("light_cell_px", 24.5, &o);
    FAIL() << "a fraction set an integer option";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "light_cell_px is 24.5; expected an integer");
  }
  EXPECT_EQ(o.light_cell_px, BlobThresholdsOptions{}.light_cell_px);
}

}  // namespace
}  // namespace patlab::vision

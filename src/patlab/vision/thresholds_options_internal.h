// The options both automatic colour fits share -- how a class's box is drawn from its pixels:
// the percentiles, the range of light it must hold for and the margin -- checked in one place
// for thresholds_auto.cpp (pixel clusters) and thresholds_blobs.cpp (patch blobs).
#pragma once

#include "patlab/core/options.h"

namespace patlab::vision::internal {

template <class Options>
OptionsChecker& CheckBoxOptions(OptionsChecker& check, const Options& o) {
  return check
      .Require("lower_percentile", o.lower_percentile,
               o.lower_percentile >= 0.0 && o.lower_percentile < 50.0, "in [0, 50)")
      .Require("upper_percentile", o.upper_percentile,
               o.upper_percentile > 50.0 && o.upper_percentile <= 100.0, "in (50, 100]")
      .Require("lighting_min_gain", o.lighting_min_gain,
               o.lighting_min_gain > 0.0 && o.lighting_min_gain <= 1.0, "in (0, 1]")
      .Require("lighting_max_gain", o.lighting_max_gain,
               o.lighting_max_gain >= 1.0 && o.lighting_max_gain <= 4.0, "in [1, 4]")
      .IntegerInRange("margin_levels", o.margin_levels, 0, 128);
}

}  // namespace patlab::vision::internal

// What both automatic colour fits share -- how a class's box is drawn from its pixels: the
// percentiles, the range of light it must hold for and the margin -- the options checked and the
// range stretched in one place, for thresholds_auto.cpp (pixel clusters) and
// thresholds_blobs_name.cpp (patch blobs).
#pragma once

#include <algorithm>
#include <cmath>

#include "patlab/core/options.h"
#include "patlab/vision/color_lut.h"

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

// The range [lo, hi] of YUV channel `channel` (0: luma) as it reads under any light intensity
// from min_gain to max_gain times the frames' (luma scales, the chroma's offset from neutral
// too), widened by margin_levels on each side and clamped to [0, 255].
inline ChannelRange StretchForLight(int lo, int hi, int channel, double min_gain, double max_gain,
                                    int margin_levels) {
  const double offset = channel == 0 ? 0.0 : 128.0;
  double a = 255, b = 0;
  for (const double gain : {min_gain, max_gain}) {
    for (const int v : {lo, hi}) {
      const double scaled = offset + gain * (v - offset);
      a = std::min(a, scaled), b = std::max(b, scaled);
    }
  }
  ChannelRange r;
  r.lo = std::clamp(static_cast<int>(std::floor(a)) - margin_levels, 0, 255);
  r.hi = std::clamp(static_cast<int>(std::ceil(b)) + margin_levels, 0, 255);
  return r;
}

}  // namespace patlab::vision::internal

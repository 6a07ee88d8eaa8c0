// What both automatic colour fits share -- how a class's box is drawn from its pixels: the
// percentiles, the range of light it must hold for and the margin -- the options checked and the
// range stretched in one place, for thresholds_auto.cpp (pixel clusters) and
// thresholds_blobs_name.cpp (patch blobs).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "patlab/camera/image.h"
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

// A YUV pixel as it reads in a frame exposed `gain` times brighter, scaled back by 1 / gain (as
// FrameDetector scales a frame to the thresholds' light, [frame] light_luma): the same pixel
// unless the exposure clipped one of its R, G and B at 255, which takes chroma from a bright
// colour (a saturated blue or yellow) that scaling back does not return.
inline std::array<uint8_t, 3> ClippedAtGain(const std::array<uint8_t, 3>& yuv, double gain) {
  int rgb[3];
  camera::YuvToRgb(yuv[0], yuv[1], yuv[2], &rgb[0], &rgb[1], &rgb[2]);
  for (int& c : rgb) c = static_cast<int>(std::lround(std::min(255.0, gain * c) / gain));
  int y = 0, u = 0, v = 0;
  camera::RgbToYuv(rgb[0], rgb[1], rgb[2], &y, &u, &v);
  return {static_cast<uint8_t>(y), static_cast<uint8_t>(u), static_cast<uint8_t>(v)};
}

// Frames up to kBrighterFramesGain times as bright as the fitted ones, once scaled to the
// thresholds' light, still show a class's colours in its box (the blob fit's boxes,
// WithClipping at kClippingGains gains). Higher: boxes of bright colours reach towards grey (set up
// at 1.6 times the light, a 3 here found 1 of 10 robots at every exposure, docs/setup.md).
inline constexpr double kBrighterFramesGain = 1.6;
inline constexpr int kClippingGains = 4;

// `pixels` and, after them, each as ClippedAtGain reads it at every gain above 1 of
// kClippingGains spread evenly (in ratio) up to max_gain: a class's pixels as frames up to
// max_gain times brighter show them, scaled back.
inline std::vector<std::array<uint8_t, 3>> WithClipping(
    const std::vector<std::array<uint8_t, 3>>& pixels, double max_gain) {
  std::vector<std::array<uint8_t, 3>> out = pixels;
  if (max_gain <= 1.0) return out;
  for (int i = 1; i <= kClippingGains; ++i) {
    const double gain = std::pow(max_gain, i / static_cast<double>(kClippingGains));
    for (const auto& p : pixels) {
      const std::array<uint8_t, 3> q = ClippedAtGain(p, gain);
      if (q != p) out.push_back(q);
    }
  }
  return out;
}

}  // namespace patlab::vision::internal

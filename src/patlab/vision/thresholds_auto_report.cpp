// The printed report of the automatic thresholds fit (thresholds_auto.h AutoThresholdsReport).
#include <string>

#include "patlab/core/format.h"
#include "patlab/vision/thresholds_auto.h"

namespace patlab::vision {

std::string AutoThresholdsReport(const AutoThresholdsFit& fit) {
  std::string out =
      StringPrintf("%-12s %9s %7s %-16s %7s %-10s %-10s %-10s %8s %s\n", "class", "pixels",
                   "labels", "mean Y,U,V", "spread", "Y", "U", "V", "separab.", "nearest");
  const auto row = [&](const AutoClassFit& c) {
    const auto range = [](const ChannelRange& r) {
      return std::to_string(r.lo) + ":" + std::to_string(r.hi);
    };
    const std::string mean = FormatFixed(c.mean_yuv[0], 0) + "," + FormatFixed(c.mean_yuv[1], 0) +
                             "," + FormatFixed(c.mean_yuv[2], 0);
    out += StringPrintf(
        "%-12s %9ld %7ld %-16s %7s %-10s %-10s %-10s %8s %s\n", c.name.c_str(), c.pixels,
        c.labelled, mean.c_str(), FormatFixed(c.spread_levels, 1).c_str(),
        range(c.range[0]).c_str(), range(c.range[1]).c_str(), range(c.range[2]).c_str(),
        c.pixels == 0 || c.nearest.empty() ? "-" : FormatFixed(c.separability, 1).c_str(),
        c.nearest.c_str());
  };
  row(fit.carpet);
  for (const AutoClassFit& c : fit.classes) row(c);
  out += "pixels looked at " + std::to_string(fit.frame_pixels) +
         "; separability = distance to the nearest class's mean / root sum of the two spreads\n";
  for (const AutoClassFit& c : fit.classes) {
    if (c.pixels == 0) out += "warning: no pixel of " + c.name + " found; its box is empty\n";
  }
  return out;
}

}  // namespace patlab::vision

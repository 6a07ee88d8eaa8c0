#include "patlab/detect/settings.h"

#include <utility>

namespace patlab::detect {

DetectorConfig MakeDetectorConfig(std::vector<std::string> palette, const DetectorOptions& options,
                                  std::vector<DetectorPattern> patterns) {
  DetectorConfig config;
  config.palette = std::move(palette);
  config.options = options;
  config.patterns = std::move(patterns);
  const Detector check(config);  // throws InputError for the first problem
  return config;
}

std::vector<OptionsProblem> Check(const FrameSettings& settings) {
  OptionsChecker check;
  if (settings.edge_loss_px) {
    check.InRange("edge_loss_px", *settings.edge_loss_px, 0.0, kMaxEdgeLossPx, "px");
  }
  if (settings.light_luma) {
    check.Require("light_luma", *settings.light_luma,
                  *settings.light_luma > 0.0 && *settings.light_luma <= 255.0, "in (0, 255]");
  }
  if (settings.binning) check.IntegerInRange("binning", *settings.binning, 1, kMaxBinning);
  return check.Take();
}

}  // namespace patlab::detect

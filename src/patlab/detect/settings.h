// The values of a detector settings file that the detection core owns: a whole configuration
// checked as the Detector checks it, and the [frame] table that camera front ends apply. Reading
// the files themselves (format and defaults: experiments/detector.toml) is
// formats/detector_settings.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/detect/detector.h"

namespace patlab::detect {

// A configuration from values, for callers that build one in code (patlab evaluate, a robot's
// vision stack without settings files); the settings files go through it too. Checks the whole
// configuration as the Detector does (palette, options, colours in the palette) and throws
// InputError for the first problem. A DetectorPattern built in code is its pattern, its key
// colours, symmetry_tolerance_mm and a codebook, e.g. GenerateCodebook(pattern,
// FindSymmetry(pattern, tolerance_mm), id_colours) (codebook.h).
DetectorConfig MakeDetectorConfig(std::vector<std::string> palette, const DetectorOptions& options,
                                  std::vector<DetectorPattern> patterns);

// The optional [frame] table of a settings file: how a camera front end (vision::FrameDetector,
// patlab detect) adapts the detector to real frames. The Detector never reads it, so detection on
// simulated blobs (simulate, evaluate, compare, scenes) is the same with or without it. An unset
// field leaves the front end's own default (vision::FrameDetectorOptions, ApplyFrameSettings).
struct FrameSettings {
  // Pixels a segmented region loses all around its patch, in [0, kMaxEdgeLossPx]
  // (vision::FrameDetectorOptions::edge_loss_px; default there 1 px).
  std::optional<double> edge_loss_px;
  // The missing-patch policy on camera frames, replacing [detector] missing_patch there: a real
  // frame regularly loses one patch of a pattern (occlusion, a sector merged with the robot's
  // body, a colour the light does not show) where simulated blobs lose none unless asked to.
  std::optional<MissingPatchPolicy> missing_patch;
  // The light the colour thresholds were fitted at, as vision::FrameLight measures a frame (the
  // median luma, 0..255; vision::FrameDetectorOptions::light_luma): each frame's colours are
  // scaled by it over the frame's own light before they are classified. In (0, 255].
  std::optional<double> light_luma;
  // The frames binned k x k before they are segmented (vision::FrameDetectorOptions::binning),
  // which patlab setup writes for frames larger than it works at. In [1, kMaxBinning].
  std::optional<int64_t> binning;  // as read; ApplyFrameSettings takes it once checked
};
inline constexpr double kMaxEdgeLossPx = 10.0;
inline constexpr int kMaxBinning = 8;

// Every broken constraint (core/options.h): edge_loss_px, when set, finite and in
// [0, kMaxEdgeLossPx]; light_luma, when set, in (0, 255]; binning, when set, in [1, kMaxBinning].
std::vector<OptionsProblem> Check(const FrameSettings& settings);

}  // namespace patlab::detect

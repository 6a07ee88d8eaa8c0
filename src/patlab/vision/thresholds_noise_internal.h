// The blob fit's boxes widened towards the camera's noise (thresholds_blobs.h, stage 4;
// thresholds_blobs_noise.cpp). A class seen in one or two blobs has a box as narrow as the noise
// of those few pixels or, once its sides are pulled in against the frame's other pixels (among
// them its own colour's patches that made no blob), narrower: another patch of that colour,
// read with noise of its own, falls out of it. So a box narrower than the class's median colour
// spread by the noise measured on the frames is widened towards that, the more the fewer blobs.
#pragma once

#include <array>
#include <vector>

#include "patlab/vision/color_lut.h"
#include "patlab/vision/thresholds_blobs.h"

namespace patlab::vision::internal {

// The camera's noise: per YUV channel how far below and above the local median (levels) the
// box percentiles (lower_percentile, upper_percentile) of the carpet's pixels lie. The carpet is
// the frames' one large area of one colour; its median is taken per cell of light_cell_px, the
// cells the light is measured on, so that the light's change across the frame is not counted
// as noise (a cell counts when at least an eighth of it is carpet, as for the light).
struct CameraNoise {
  std::array<int, 3> below = {}, above = {};
  long pixels = 0;  // carpet pixels measured; 0: none, no noise known
};
CameraNoise MeasureCarpetNoise(const std::vector<NormalisedFrame>& frames,
                               const BlobThresholdsOptions& options);
// The counts MeasureCarpetNoise reads (NormalisedFrame::carpet_residual_counts), made once per
// frame by NormaliseFrame: every fit of a normalised frame shares them.
void CountCarpetResiduals(int light_cell_px, NormalisedFrame* frame);

// The per-channel median of `pixels` (not empty): a class's typical colour, which its box's
// tightening keeps inside and its noise's box is centred on.
std::array<int, 3> MedianColour(const std::vector<std::array<uint8_t, 3>>& pixels);

// The noise's box of a class: its `median` colour less noise.below and plus noise.above,
// plus margin_levels on each side (clamped to 0..255), what a patch of the class's colour reads
// as under the light its blobs were seen in. (Not stretched for the range of light, as the
// percentile box is: that stretch is a prior that the box's tightening trims against the frame's
// other pixels, while the noise is measured.)
std::array<ChannelRange, 3> NoiseBox(const std::array<int, 3>& median, const CameraNoise& noise,
                                     const BlobThresholdsOptions& options);

// Each side of `box` narrower than the noise's box (NoiseBox) moves `weight` of the way out to it:
// the fit gives 1 / (1 + the class's blobs), the noise's box weighing as one blob against the
// class's own, so a class seen in one blob takes half the gap and one seen in many keeps nearly
// its box. Returns the levels added per channel, both sides together.
std::array<int, 3> WidenToNoise(const std::array<int, 3>& median, const CameraNoise& noise,
                                double weight, const BlobThresholdsOptions& options,
                                std::array<ChannelRange, 3>* box);

}  // namespace patlab::vision::internal

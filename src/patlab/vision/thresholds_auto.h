// Automatic colour thresholds, behind `patlab thresholds --auto` (docs/thresholds.md): one or more
// frames of a camera and the colour classes the patterns need (names of the colour vocabulary,
// core/colour_names.h) -> the thresholds `patlab detect -t` reads, with no pixel labelled by hand.
//
// 1. Carpet: the dominant colour, the fullest cell of a 16-level YUV histogram, refined to the
//    pixels within gate_sigmas of its mean per channel. Its pixels are no class's.
// 2. Classes: every other pixel in a space where a change of light intensity moves little
//    (hue angle in the UV plane, chroma over luma, log luma; a gain on RGB leaves the first two
//    alone), assigned to the nearest class seed, the vocabulary's typical colour (or the mean of
//    a class's labelled pixels, when labels are given), and only within gate_sigmas of it, so
//    clutter far from every seed joins no class (clutter of a class's hue does: see
//    docs/thresholds.md for what that does on real frames); a connected region of one
//    class larger than a patch can be (max_patch_fraction) leaves it. A few k-means rounds move
//    each seed to its cluster. Achromatic classes (white, black) ignore the hue.
// 3. Boxes: per YUV channel the percentiles of the class's pixels, stretched for light
//    intensities from lighting_min_gain to lighting_max_gain times the frames' (luma scaled, the
//    chroma's offset from neutral scaled), plus margin_levels: boxes fitted on one exposure hold
//    on another. A box that would catch the carpet's core (its mean +- 2.5 sd per channel,
//    stretched for the same lights) is cut on the one channel and side that keeps most of the
//    class's pixels.
// Per class the result reports its pixel count, spread and a separability: the distance of its
// mean to the nearest other class's (or the carpet's) mean in YUV over the root sum of the two
// spreads (below 2 the two overlap, above 4 they are well apart).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/colour_names.h"
#include "patlab/core/options.h"
#include "patlab/vision/color_lut.h"

namespace patlab::vision {

struct AutoThresholdsOptions {
  // Pixels whose chroma (distance of (U, V) from neutral, levels) is below this take part only
  // in achromatic classes (white, black). Higher: fewer grey pixels taken for pale colours, pale
  // patches missed. In [0, 128].
  double min_chroma_levels = 14.0;
  // A pixel joins a class only within this many spreads of its centre (per feature). Larger:
  // more of a patch's blurred rim, more clutter. In (0, 10].
  double gate_sigmas = 3.0;
  int iterations = 5;  // k-means rounds, in [0, 50]
  // Percentiles of a class's pixels per channel that bound its box (nearest rank), in [0, 50)
  // and (50, 100].
  double lower_percentile = 2.0;
  double upper_percentile = 98.0;
  // The range of light intensity, relative to the frames fitted on, the boxes must hold for, in
  // (0, 1] and [1, 4]. Wider: robust to other exposures and shadows, more overlap of close hues.
  double lighting_min_gain = 0.7;
  double lighting_max_gain = 1.4;
  int margin_levels = 4;  // levels added on each side of every bound, in [0, 128]
  // Patches are small: after each assignment a 4-connected region of one class larger than this
  // fraction of its frame's pixels (a field line, a lit stretch of carpet, a wall) leaves the
  // class. Smaller: big patches (close cameras) are lost; larger: lines and glare widen boxes.
  // In (0, 1].
  double max_patch_fraction = 0.004;
};

std::vector<OptionsProblem> Check(const AutoThresholdsOptions& options);
void Validate(const AutoThresholdsOptions& options);

// Pixels of one frame labelled by hand (a labels file's points, rectangles or mask, LabelPixels):
// labels[i] = -1 or an index into class_names. Labelled pixels always belong to their class and,
// when there are at least 5, their mean is its seed; labels of several frames are pooled.
struct LabelledFrame {
  const camera::Image* image = nullptr;
  std::vector<int> labels;
  std::vector<std::string> class_names;
};

struct AutoClassFit {
  std::string name;
  long pixels = 0;                         // pixels of the frames in the cluster
  long labelled = 0;                       // of those, labelled by hand
  long blobs = 0;                          // blobs named this class (FitThresholdsFromBlobs)
  std::array<double, 3> mean_yuv = {};     // the cluster's mean (levels)
  double spread_levels = 0.0;              // RMS distance from the mean per channel (levels)
  double separability = 0.0;               // see the header comment; inf when alone
  std::string nearest;                     // the class (or "carpet") it is nearest to
  std::array<ChannelRange, 3> range = {};  // its box (Y, U, V)
  // Levels the blob fit widened the box by per channel (both sides together) to hold the
  // class's median colour spread by the camera's noise (AutoThresholdsFit::noise_levels) and the
  // margin; 0: not widened.
  std::array<int, 3> widened_levels = {};
  // Pixels of regions too narrow for a blob that the blob fit did not count against the class's
  // box, the regions holding a pixel of its median colour spread by the camera's noise: its
  // colour's patches whose cores the segmentation cut to slivers. 0: none.
  long thin_alike = 0;
};

struct AutoThresholdsFit {
  Thresholds thresholds;              // YUV, the classes in the order asked for
  AutoClassFit carpet;                // the dominant colour (not a class unless asked for)
  std::vector<AutoClassFit> classes;  // in the order asked for
  long frame_pixels = 0;              // pixels looked at, over all frames
  // The blob fit's measure of the camera's noise: per channel the range (levels) that the box
  // percentiles span of the carpet's pixels about its median per light cell; 0 for the pixel
  // clustering.
  std::array<int, 3> noise_levels = {};
};

// The vocabulary's entries of the colour classes asked for, in their order (aliases resolved).
// Throws InputError for none or more than kMaxColorClasses, an unknown name, or one asked twice.
std::vector<const ColourEntry*> PaletteEntries(const std::vector<std::string>& class_names,
                                               const ColourVocabulary& vocabulary);

// `class_names` must be colours of `vocabulary` (InputError naming the unknown one) and distinct;
// at most kMaxColorClasses. A class named "carpet" (or an alias) is the carpet cluster. Frames
// may have any PixelFormat and size. InputError for no frames or a labelled class not asked for.
AutoThresholdsFit FitThresholdsAuto(const std::vector<const camera::Image*>& frames,
                                    const std::vector<std::string>& class_names,
                                    const ColourVocabulary& vocabulary,
                                    const AutoThresholdsOptions& options,
                                    const std::vector<LabelledFrame>& labels = {});

// Each class's separability and nearest class (or "carpet"): see the header comment.
void ComputeSeparability(AutoThresholdsFit* fit);

// The report for people: the carpet, then per class pixels, mean, spread, box, separability.
std::string AutoThresholdsReport(const AutoThresholdsFit& fit);

}  // namespace patlab::vision

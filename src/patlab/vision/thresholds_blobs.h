// Colour classes from patch blobs, behind `patlab setup` (docs/setup.md, docs/thresholds.md): the
// frames of a camera and the colour classes the patterns need (names of the colour vocabulary,
// core/colour_names.h) -> the YUV boxes `patlab detect` reads, with no pixel labelled by hand.
// Where thresholds_auto.h clusters single pixels, this classifies whole blobs, so that a
// patch's blurred rim, a field line or the light falling off towards a corner cannot drag a
// class:
//
// 1. Light (NormaliseFrame): the carpet is the dominant colour; its brightness, measured on a
//    grid of cells and smoothed, is the frame's light. A pixel is a candidate when its linear
//    RGB, scaled by the carpet's mean brightness over the local one, lies farther than
//    standout_delta_e (CIELAB Delta E) from the carpet's scaled colour: it stands out from the
//    carpet around it, in a dark corner as under a lamp. (Colours are named unscaled: a patch
//    need not follow the carpet's light -- on the VSS frame the lime patches have one RGB from
//    the lit centre to the dark corner, while the carpet's brightness varies threefold.)
// 2. Blobs (FindColourBlobs): the candidates, cut into regions of one colour by Felzenszwalb and
//    Huttenlocher's graph segmentation (IJCV 2004; 4-neighbour edges weighted by CIELAB Delta E,
//    threshold segment_k / size); regions of a patch's size and width are the blobs, each with
//    its median colour.
// 3. Names (NameBlobClusters): blobs of one colour are clustered (complete linkage on a weighted
//    Delta E in which lightness, the first thing light changes, counts less: a cluster's blobs
//    all lie within cluster_distance of each other, so dark blobs do not chain through the dull
//    ones between them), and the clusters are named: each class of the palette takes the
//    cluster nearest its vocabulary entry (hue, chroma and lightness over the spreads below), one
//    cluster per class, the cheapest pairs first, so two clusters competing for one name go to
//    the two names that fit them best together; a further cluster joins a class when it is near
//    that class's cluster (for white and black, lightness counting in full) and fits the class's
//    entry, and no other class's better. What is named nothing is clutter.
// 4. Boxes: per class the percentiles of its blobs' pixels in YUV, stretched for light
//    intensities lighting_min_gain..lighting_max_gain, plus margin_levels, and widened to the
//    percentiles of those pixels as frames up to internal::kBrighterFramesGain times brighter
//    clip them, scaled back (FrameDetector scales frames to the fitted light, [frame]
//    light_luma); each box's sides are then pulled in wherever that drops more than
//    negative_weight pixels of everything else (carpet, other classes, clutter; not the pixels
//    of regions larger than a patch, such as field lines, walls and the frame's dark margins,
//    whose blobs the detector rejects by their area; nor, for a class, the regions of a patch's
//    area too narrow for a blob that hold a pixel of the class's noise box, below: its own small
//    patches whose cores the segmentation cut to slivers) per pixel of the class's own or of its
//    clipped readings, never past the class's median colour. Last, a box narrower than the
//    class's median colour spread by the camera's noise (measured on the carpet) is widened
//    towards that, by 1 / (1 + its blobs) of the gap (thresholds_noise_internal.h), so that a
//    class seen in one or two blobs still holds its colour's other patches.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/colour_names.h"
#include "patlab/core/options.h"
#include "patlab/vision/thresholds_auto.h"

namespace patlab::vision {

struct BlobThresholdsOptions {
  // A blob's area range in pixels: what a patch can cover. `patlab setup` sets it from the
  // calibration and the patterns' patch sizes. min in [1, 1e6], max >= min.
  double min_blob_area_px = 6.0;
  double max_blob_area_px = 2000.0;
  // A blob's spread across its narrowest direction (the smaller principal axis's standard
  // deviation, px) must reach this: a disc of radius r has r / 2, a line w px wide w / sqrt(12),
  // so field lines and the thin rims where two colours blend are no blobs. `patlab setup` sets it
  // to 0.3 times the smallest patch's radius in px. In [0, 1000].
  double min_blob_sigma_px = 1.0;
  // The light is measured on cells of this size (px) and smoothed over 3 x 3 cells. Smaller:
  // follows sharper changes of light, more noise where robots cover the carpet. In [4, 512].
  int light_cell_px = 24;
  // The normalising gain is held within [1 / max_light_gain, max_light_gain]: a dark carpet's
  // brightness is measured with little precision, and a patch already clipped at 255 cannot be
  // brightened. In [1, 16].
  double max_light_gain = 2.0;
  // A pixel is a candidate when its light-normalised colour lies this far (CIELAB Delta E) from
  // the carpet's. Higher: fewer dull patches, less clutter. In (0, 200].
  double standout_delta_e = 20.0;
  // Felzenszwalb's k (Delta E x px): larger joins more (whole robot tops), smaller cuts a patch
  // along its noise. In (0, 10000].
  double segment_k = 60.0;
  // Blobs whose colours lie closer than this (weighted Delta E) join one cluster. In (0, 200].
  double cluster_distance = 24.0;
  // How much a lightness difference counts against a chroma difference in blob distances
  // (light changes lightness first). In (0, 1].
  double lightness_weight = 0.5;
  // A cluster's distance to a vocabulary entry: (hue difference / hue_spread_deg)^2 +
  // (lightness difference / lightness_spread)^2 + (log chroma ratio / chroma_spread)^2 for
  // colours (a cluster with less chroma than achromatic_chroma is no colour's); (chroma /
  // achromatic_chroma)^2 + the lightness term for white and black. A cluster farther than
  // max_name_cost from every class is clutter.
  double hue_spread_deg = 30.0;     // in (0, 180]
  double lightness_spread = 40.0;   // CIELAB L*, in (0, 100]
  double chroma_spread = 1.0;       // natural log of the chroma ratio, in (0, 10]
  double achromatic_chroma = 12.0;  // CIELAB chroma, in (0, 100]
  double max_name_cost = 9.0;       // in (0, 1000]
  // Box percentiles of a class's blob pixels per channel, in [0, 50) and (50, 100].
  double lower_percentile = 2.0;
  double upper_percentile = 98.0;
  // The range of light intensity the boxes must hold for, relative to the frames fitted on, in
  // (0, 1] and [1, 4]; luma scales with it, the chroma's offset from neutral too.
  double lighting_min_gain = 0.7;
  double lighting_max_gain = 1.4;
  int margin_levels = 3;  // levels added on each side of every bound, in [0, 128]
  // A side of a box moves in while that removes more than this many other pixels (but those of
  // regions larger than a patch) per own pixel lost. Lower: tighter boxes. In (0, 100].
  double negative_weight = 2.0;
};

std::vector<OptionsProblem> Check(const BlobThresholdsOptions& options);
void Validate(const BlobThresholdsOptions& options);

// The options by name (`patlab setup --colour-option NAME=VALUE`, patlab.setup(colour_options=)):
// every field above but the blob area range and spread, which setup sets from the calibration.
// SetBlobThresholdsOption: InputError for another name (listing these) or a non-integer value of
// an integer option; the range is Check's.
std::vector<std::string> BlobThresholdsOptionNames();
void SetBlobThresholdsOption(const std::string& name, double value, BlobThresholdsOptions* options);

// A frame after stage 1: per pixel (row-major) its YUV as the lookup table sees it, its CIELAB
// colour and how far it stands out from the carpet around it (FindColourBlobs takes the pixels
// farther than its options' standout_delta_e, so fits at several thresholds share one frame).
struct NormalisedFrame {
  int width_px = 0, height_px = 0;
  std::vector<std::array<uint8_t, 3>> yuv;
  std::vector<std::array<float, 3>> lab;
  // The squared Delta E of each pixel's light-normalised colour from the carpet's.
  std::vector<double> standout_delta_e2;
  std::array<double, 3> carpet_lab = {};  // the carpet's mean colour (light-normalised)
  std::array<double, 3> carpet_yuv = {};  // the carpet's mean YUV
  long carpet_pixels = 0;
  std::vector<uint8_t> carpet;  // 1 where a pixel is the carpet's
  // The camera's noise on the carpet (thresholds_noise_internal.h): per YUV channel, how many of
  // the carpet's pixels lie d levels from their light cell's carpet median, at index d + 255.
  std::array<std::vector<long>, 3> carpet_residual_counts;
};

NormalisedFrame NormaliseFrame(const camera::Image& image, const BlobThresholdsOptions& options);

// A region of one colour standing out from the carpet, of a patch's size.
struct ColourBlob {
  int frame = 0;
  std::vector<int> pixels;         // indices into the frame's pixels
  double x_px = 0.0, y_px = 0.0;   // centroid
  double sigma_minor_px = 0.0;     // spread across its narrowest direction
  std::array<double, 3> lab = {};  // median CIELAB of its pixels
  int cluster = -1;                // after NameBlobClusters
  int name = -1;                   // class index, -1 clutter
};

// `oversize` (optional) receives 1 for every pixel of a region larger than a patch; `narrow`
// (optional) the regions of a patch's area too narrow for a blob (spread under
// min_blob_sigma_px), each as its pixels' indices: among them a small patch's core that the
// segmentation cut to a sliver.
std::vector<ColourBlob> FindColourBlobs(const NormalisedFrame& frame, int frame_index,
                                        const BlobThresholdsOptions& options,
                                        std::vector<uint8_t>* oversize = nullptr,
                                        std::vector<std::vector<int>>* narrow = nullptr);

// CIELAB (D65) of an sRGB colour.
std::array<double, 3> SrgbToLab(const std::array<uint8_t, 3>& rgb);

// The cost of calling a colour `lab` by `entry` (header comment, stage 3).
double NameCost(const std::array<double, 3>& lab, const ColourEntry& entry,
                const BlobThresholdsOptions& options);

// A cluster of blobs: its mean colour, its blob count and the class it was named (-1: none).
struct BlobCluster {
  std::array<double, 3> lab = {};
  int blobs = 0;
  int name = -1;
};

// Clusters `blobs` and names the clusters with `entries` (the classes, in order); sets every
// blob's cluster and name.
std::vector<BlobCluster> NameBlobClusters(const std::vector<const ColourEntry*>& entries,
                                          const BlobThresholdsOptions& options,
                                          std::vector<ColourBlob>* blobs);

// The whole fit. The result's classes follow `class_names`; a class that named no blob gets an
// empty box (catches nothing) and 0 pixels. `clusters` (optional) receives the named and
// unnamed clusters for the report.
AutoThresholdsFit FitThresholdsFromBlobs(const std::vector<const camera::Image*>& frames,
                                         const std::vector<std::string>& class_names,
                                         const ColourVocabulary& vocabulary,
                                         const BlobThresholdsOptions& options,
                                         std::vector<BlobCluster>* clusters = nullptr);
// The same on frames already normalised (NormaliseFrame with these options' light_cell_px and
// max_light_gain): fits of one frame at several stand-out thresholds, segmentation scales or
// blob area ranges share its normalisation.
AutoThresholdsFit FitThresholdsFromBlobs(const std::vector<NormalisedFrame>& normalised,
                                         const std::vector<std::string>& class_names,
                                         const ColourVocabulary& vocabulary,
                                         const BlobThresholdsOptions& options,
                                         std::vector<BlobCluster>* clusters = nullptr);

}  // namespace patlab::vision

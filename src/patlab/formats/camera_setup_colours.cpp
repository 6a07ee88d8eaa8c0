// The colour classes of `patlab setup` (camera_setup.h): the blobs' fit at the settings'
// segment_k and at its neighbouring scales, and the pixel clustering, weighed by the robots each
// decodes through the files setup writes.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "patlab/core/colour_names.h"
#include "patlab/core/error.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup_internal.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/vision/thresholds_auto.h"
#include "patlab/vision/thresholds_blobs.h"

namespace patlab::formats {

namespace {

double LargestPatchMm(const detect::DetectorConfig& config) {
  double r = 0.0;
  for (const detect::DetectorPattern& p : config.patterns)
    for (const Patch& patch : p.pattern.patches) r = std::max(r, patch.radius_mm);
  return r;
}

std::vector<std::string> PaletteClasses(const detect::DetectorConfig& config,
                                        const SetupOptions& o) {
  const ColourVocabulary& vocabulary = io::DefaultColourVocabulary();
  std::vector<std::string> classes;
  for (const std::string& name : config.palette) {
    const ColourResolution c = ResolveColourName(vocabulary, name);
    if (!c.known) throw InputError(o.settings_path + ": " + UnknownColourMessage(vocabulary, c));
    classes.push_back(name);
  }
  return classes;
}

// The segmentation scales the blobs' fit also tries, relative to the given segment_k (header).
constexpr std::array<double, 2> kSegmentScales = {2.0 / 3.0, 1.5};

// The frames normalised for the blobs' fits: r's shared ones where they were normalised from
// these frames with these options, else normalised now and kept in r for the next fit.
const std::vector<vision::NormalisedFrame>& NormalisedFrames(
    const std::vector<const camera::Image*>& frames, const vision::BlobThresholdsOptions& o,
    SetupResult* r) {
  const SetupResult::NormalisedFrames* kept = r->normalised_frames.get();
  if (kept != nullptr && kept->frames == frames && kept->light_cell_px == o.light_cell_px &&
      kept->max_light_gain == o.max_light_gain && kept->standout_delta_e == o.standout_delta_e) {
    return kept->normalised;
  }
  auto made = std::make_shared<SetupResult::NormalisedFrames>();
  made->frames = frames;
  made->light_cell_px = o.light_cell_px;
  made->max_light_gain = o.max_light_gain;
  made->standout_delta_e = o.standout_delta_e;
  for (const camera::Image* frame : frames)
    made->normalised.push_back(vision::NormaliseFrame(*frame, o));
  r->normalised_frames = std::move(made);
  return r->normalised_frames->normalised;
}

vision::AutoThresholdsFit FitBlobColours(const std::vector<const camera::Image*>& frames,
                                         const detect::DetectorConfig& config,
                                         const SetupOptions& o, double segment_k, SetupResult* r,
                                         std::vector<vision::BlobCluster>* clusters) {
  vision::BlobThresholdsOptions colours = o.colours;
  colours.segment_k = segment_k;
  if (r->mm_per_px > 0.0) {
    SetupBlobAreas(r->smallest_patch_px, LargestPatchMm(config) / r->mm_per_px, &colours);
  }
  return vision::FitThresholdsFromBlobs(NormalisedFrames(frames, colours, r),
                                        PaletteClasses(config, o), io::DefaultColourVocabulary(),
                                        colours, clusters);
}

}  // namespace

void internal::FitColours(const std::vector<const camera::Image*>& frames,
                          const detect::DetectorConfig& config, const SetupOptions& o,
                          SetupResult* r) {
  r->segment_k = o.colours.segment_k;
  r->thresholds = FitBlobColours(frames, config, o, r->segment_k, r, &r->colour_clusters);
}

void internal::ChooseColourFit(const std::vector<const camera::Image*>& frames,
                               const detect::DetectorConfig& config, const SetupOptions& o,
                               const std::string& calibration_text,
                               const std::string& settings_text, SetupResult* r) {
  const camera::Calibration calibration = ParseCalibration(calibration_text, "calibration.toml");
  r->robots_by_blobs =
      internal::DecodedRobots(frames, r->thresholds.thresholds, calibration, settings_text);
  r->robots_by_segment_k = {{r->segment_k, r->robots_by_blobs}};
  const double given_k = r->segment_k;
  for (const double scale : kSegmentScales) {
    std::vector<vision::BlobCluster> clusters;
    vision::AutoThresholdsFit fit =
        FitBlobColours(frames, config, o, given_k * scale, r, &clusters);
    const int robots = internal::DecodedRobots(frames, fit.thresholds, calibration, settings_text);
    r->robots_by_segment_k.push_back({given_k * scale, robots});
    if (robots <= r->robots_by_blobs) continue;
    r->robots_by_blobs = robots, r->segment_k = given_k * scale;
    r->thresholds = std::move(fit), r->colour_clusters = std::move(clusters);
  }
  vision::AutoThresholdsFit pixels = vision::FitThresholdsAuto(
      frames, PaletteClasses(config, o), io::DefaultColourVocabulary(), o.thresholds);
  r->robots_by_pixels =
      internal::DecodedRobots(frames, pixels.thresholds, calibration, settings_text);
  if (r->robots_by_pixels > r->robots_by_blobs) {
    r->thresholds = std::move(pixels);
    r->colour_clusters.clear();
    r->colour_fit = "pixels";
  }
}

}  // namespace patlab::formats

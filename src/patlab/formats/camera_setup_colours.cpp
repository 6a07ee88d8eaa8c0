// The colour classes of `patlab setup` (camera_setup.h): the blobs' fit at the settings'
// segment_k and standout_delta_e and at their neighbouring values, and the pixel clustering,
// weighed by the robots each decodes through the files setup writes.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "patlab/core/colour_names.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
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

// The blobs' fits tried, relative to the given standout_delta_e and segment_k (header), in the
// order a tie keeps: the given stand-out threshold before the lower one, the given scale first.
constexpr std::array<double, 2> kStandoutScales = {1.0, 0.7};
constexpr std::array<double, 3> kSegmentScales = {1.0, 2.0 / 3.0, 1.5};

// The frames normalised for the blobs' fits: r's shared ones where they were normalised from
// these frames with these options, else normalised now and kept in r for the next fit.
const std::vector<vision::NormalisedFrame>& NormalisedFrames(
    const std::vector<const camera::Image*>& frames, const vision::BlobThresholdsOptions& o,
    SetupResult* r) {
  const SetupResult::NormalisedFrames* kept = r->normalised_frames.get();
  if (kept != nullptr && kept->frames == frames && kept->light_cell_px == o.light_cell_px &&
      kept->max_light_gain == o.max_light_gain) {
    return kept->normalised;
  }
  auto made = std::make_shared<SetupResult::NormalisedFrames>();
  made->frames = frames;
  made->light_cell_px = o.light_cell_px;
  made->max_light_gain = o.max_light_gain;
  for (const camera::Image* frame : frames)
    made->normalised.push_back(vision::NormaliseFrame(*frame, o));
  r->normalised_frames = std::move(made);
  return r->normalised_frames->normalised;
}

vision::AutoThresholdsFit FitBlobColours(const std::vector<const camera::Image*>& frames,
                                         const detect::DetectorConfig& config,
                                         const SetupOptions& o, double standout_delta_e,
                                         double segment_k, SetupResult* r,
                                         std::vector<vision::BlobCluster>* clusters) {
  vision::BlobThresholdsOptions colours = o.colours;
  colours.standout_delta_e = standout_delta_e;
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
  r->standout_delta_e = o.colours.standout_delta_e;
  r->thresholds =
      FitBlobColours(frames, config, o, r->standout_delta_e, r->segment_k, r, &r->colour_clusters);
}

void internal::ChooseColourFit(const std::vector<const camera::Image*>& frames,
                               const detect::DetectorConfig& config, const SetupOptions& o,
                               const std::string& calibration_text,
                               const std::string& settings_text, SetupResult* r) {
  const camera::Calibration calibration = ParseCalibration(calibration_text, "calibration.toml");
  const double given_delta_e = r->standout_delta_e, given_k = r->segment_k;
  r->robots_by_blobs =
      internal::DecodedRobots(frames, r->thresholds.thresholds, calibration, settings_text);
  r->blob_fits = {{given_delta_e, given_k, r->robots_by_blobs}};
  for (const double standout_scale : kStandoutScales) {
    for (const double segment_scale : kSegmentScales) {
      if (standout_scale == 1.0 && segment_scale == 1.0) continue;  // FitColours' fit, above
      const double delta_e = given_delta_e * standout_scale, k = given_k * segment_scale;
      std::vector<vision::BlobCluster> clusters;
      vision::AutoThresholdsFit fit = FitBlobColours(frames, config, o, delta_e, k, r, &clusters);
      const int robots =
          internal::DecodedRobots(frames, fit.thresholds, calibration, settings_text);
      r->blob_fits.push_back({delta_e, k, robots});
      if (robots <= r->robots_by_blobs) continue;
      r->robots_by_blobs = robots, r->standout_delta_e = delta_e, r->segment_k = k;
      r->thresholds = std::move(fit), r->colour_clusters = std::move(clusters);
    }
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

std::string internal::ColourFitText(const SetupResult& r) {
  std::string s = "colour fit: " + r.colour_fit;
  if (r.colour_fit == "blobs") {
    s += " at standout_delta_e " + FormatSignificant(r.standout_delta_e, 3) + ", segment_k " +
         FormatSignificant(r.segment_k, 3);
  }
  s += " (robots decoded by the blobs";
  for (size_t i = 0; i < r.blob_fits.size(); ++i) {
    const SetupResult::BlobFitTry& t = r.blob_fits[i];
    if (i == 0 || t.standout_delta_e != r.blob_fits[i - 1].standout_delta_e) {
      s += (i == 0 ? " at standout_delta_e " : "; at standout_delta_e ") +
           FormatSignificant(t.standout_delta_e, 3) + ", segment_k ";
    } else {
      s += ", ";
    }
    s += FormatSignificant(t.segment_k, 3) + ": " + std::to_string(t.robots);
  }
  return s + "; by pixels " + std::to_string(r.robots_by_pixels) +
         "; the most wins, a tie keeps the earlier, then blobs)\n";
}

}  // namespace patlab::formats

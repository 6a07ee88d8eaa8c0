// The real-frame front end of the detector: a frame (file or image) in; blobs, detections,
// counters and stage times out. It owns the vision pipeline (stages 2-5 of pipeline.h), the
// camera calibration, and -- when patterns are to be detected -- a detect::Detector with the
// mapping from colour classes to the detector's palette (by name; classes the palette does not
// name are not shown to the detector). This is what `patlab detect` runs per frame; a robot's
// vision stack can call it the same way:
//
//   vision::FrameDetectorOptions options;
//   vision::ApplyFrameSettings(formats::LoadFrameSettings(s), &options);  // the file's [frame]
//   vision::FrameDetector frames(LoadThresholds(t), LoadCalibration(c),
//                                formats::LoadDetectorSettings(s), options);
//   const vision::FrameResult& result = frames.DetectFile("frame.png");
//   for (const detect::Detection& d : result.detections) ...
//
// With FrameDetectorOptions::debug_dir set, the numbered per-stage debug images of each frame are
// written there (apriltag's `debug` flag and debug_*.pnm are the model; see DebugImageNames).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/camera/image.h"
#include "patlab/core/options.h"
#include "patlab/core/timeprofile.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/key_diagnosis.h"
#include "patlab/detect/settings.h"
#include "patlab/vision/pipeline.h"

namespace patlab::vision {

struct FrameDetectorOptions {
  SegmenterOptions segmenter;
  // Size of raw UYVY frames (.yuv .uyvy .raw files), which carry no header. 0 x 0: no raw
  // frames expected (reading one is then an error that asks for the size).
  int raw_width_px = 0;
  int raw_height_px = 0;
  // When not empty, every frame's per-stage debug images are written into this directory (created
  // if needed) as PNGs named by DebugImageNames. Costs a PNG encode per image: for debugging.
  std::string debug_dir;
  // Time the stages into FrameResult::profile and FrameResult::detect_profile. Off: no clock is
  // read.
  bool collect_timing = false;
  // Record why each key candidate became a detection or not (FrameResult::explanations; the
  // debug image 6_detect marks them). Off: the detector records nothing.
  bool explain = false;
  // Pixels a segmented region loses all around its patch, in [0, 10]: the patch's boundary
  // pixels are mixed with the surroundings by the optics' blur and by chroma sampled at half
  // resolution (Bayer demosaicing, 4:2:2 and JPEG 4:2:0), and thresholds made from patch
  // interiors miss them. The detector's lower area bound is area_ratio_min times the area of the
  // patch shrunk by this rim (at the camera's mm per px on the robot-top plane), not times its
  // full area: a 40 mm dot seen at 6 mm per px loses half its area to a 1 px rim, a 50 mm dot at
  // 1 mm per px 8%. 0 = the full area (the detector's own test). A settings file's [frame]
  // edge_loss_px; patlab detect --edge-loss-px.
  double edge_loss_px = 1.0;
  // The missing-patch policy on frames; unset: the detector settings' own ([detector]
  // missing_patch). A settings file's [frame] missing_patch (experiments/detector.toml: "fit";
  // docs/detect.md, "Settings that travel").
  std::optional<detect::MissingPatchPolicy> missing_patch;
  // The light the thresholds were fitted at (FrameLight of the frames they come from); 0: none,
  // every frame is classified as it is. Otherwise a frame whose own light differs from it by more
  // than kLightTolerance has its R, G and B scaled by light_luma over its light (clipped at 255)
  // before it is classified: an exposure or a lamp's intensity scales a colour's luma and its
  // chroma's offset from neutral alike, along a ray through neutral, which a fixed YUV box holds
  // only over a narrow range (docs/setup.md, "Lighting"). A settings file's [frame] light_luma,
  // which patlab setup writes. In [0, 255].
  double light_luma = 0.0;
  // Each frame binned `binning` x `binning` (camera::BinImage: the mean of each block) before
  // anything else, and segmented with the calibration resized to match (Calibration::Resized):
  // frames must still have the calibration's size. patlab setup works on frames larger than
  // about a thousand pixels binned so, and writes the factor as the settings' [frame] binning,
  // so that the colour boxes it fits (on binned pixels, whose noise the averaging lowers) and
  // the detector see frames alike. Positions come out in mm as ever; pixel positions (regions,
  // debug images) are the binned frame's. In [1, detect::kMaxBinning].
  int binning = 1;
};

// A frame's light: the median luma (BT.601 Y, 0..255) of every 4th pixel of every 4th row. The
// carpet covers most of a field camera's view, so this is the carpet's brightness, which scales
// with the exposure and the lamps; the robots and the lines moving leave it nearly alone.
double FrameLight(const camera::ImageView& image);

// Frames whose light is within this fraction of FrameDetectorOptions::light_luma are classified
// as they are (no copy).
inline constexpr double kLightTolerance = 0.02;

// Every broken constraint (core/options.h): the segmenter's, a raw size that is either 0 x 0 or a
// positive even width and a positive height, and edge_loss_px as detect::Check(FrameSettings).
std::vector<OptionsProblem> Check(const FrameDetectorOptions& options);
void Validate(const FrameDetectorOptions& options);

// The set fields of a settings file's [frame] table (formats::LoadFrameSettings) into `options`.
void ApplyFrameSettings(const detect::FrameSettings& settings, FrameDetectorOptions* options);

// What FrameDetector does to a detector configuration for frames of `calibration`: the
// calibration's recorded residual on the robot-top plane widens the geometric tolerance, and the
// lower area bound allows for the segmentation's edge loss (FrameDetectorOptions::edge_loss_px).
// Every front end that turns segmented regions into blobs applies it (patlab camtrack does), so
// the detector sees rendered and real frames alike.
void AdaptToCamera(detect::DetectorConfig& config, const camera::Calibration& calibration,
                   double edge_loss_px);

// The debug images of a frame whose file stem is `stem`, one per stage that has a picture, named
// "<stem>.<stage number>_<stage name>.png" after kFrameStageNames:
//   <stem>.2_colour_lookup.png - the class image: each classified pixel in its class's colour;
//   <stem>.4_regions.png       - the frame dimmed, class boundaries, each kept region's bounding
//                                box and centroid;
//   <stem>.5_blobs_to_mm.png   - the blobs mapped to the plane (the detector's input when patterns
//                                are detected), as discs of their area at their centroids;
//   <stem>.6_detect.png        - the regions image with each detection's circle, heading and ID;
//                                with FrameDetectorOptions::explain, every key candidate that is
//                                no detection marked by a red ring and a letter: A key area,
//                                N too few neighbours, G geometry, C colours, X conflict lost,
//                                M a missing-patch fit whose missing patch shows another colour.
// The last only when patterns are detected.
std::vector<std::string> DebugImageNames(const std::string& stem, bool with_detections);

// What the frame shows where a missing-patch fit (detect::DetectionStatus::kMissingPatch) puts
// its missing patch: the pixels of the patch's footprint (the patch shape placed by the fitted
// pose on the robot-top plane, every pixel whose centre maps inside it) counted by their colour
// class. `own`: a class whose palette colour the patch may have (a fixed patch's colour, an ID
// patch's codebook colours, a key's team colours) -- the patch is there but was not a blob of its
// own (merged with a dark body, cut up, outside the area range); `other`: another colour of the
// detector's palette; the rest is unclassified or of classes the detector does not see (a colour
// the light does not show, an occluder). A fit whose missing patch shows clearly another colour
// -- more than kMissingPatchOtherMax of its footprint -- is no robot of this pattern there and is
// dropped from the detections (`rejected`).
struct MissingPatchLook {
  detect::Detection detection;  // the fit as the detector returned it
  int key_blob = -1;            // its key blob (index into FrameResult::detector_blobs)
  int pixels = 0;               // footprint pixels inside the image
  int own = 0, other = 0;       // of them: the patch's own colours, other palette colours
  bool rejected = false;
};
// More than half of the missing patch's footprint in other palette colours: "clearly another
// colour" (a majority, so that blur at the rim or a neighbour's edge does not decide).
inline constexpr double kMissingPatchOtherMax = 0.5;

// A region found in a frame binned k x k (FrameDetectorOptions::binning), in the frame's own
// pixels: binned pixel (i, j) covers the frame's pixels k i .. k i + k - 1 (and j alike), so its
// centre is at k (i + 0.5) - 0.5; the area counts k^2 frame pixels for each binned one.
Region InFramePixels(const Region& binned, int k);

// One frame's results; valid until the next call on the FrameDetector that returned it. Every
// pixel position and area is in the frame's own pixels, binned or not.
struct FrameResult {
  std::string frame;                // the path (or name) of the frame
  std::vector<detect::Blob> blobs;  // stage 5, colour = class index into the thresholds
  // Per blob: the region it came from (pixel centroid and area).
  std::vector<Region> blob_regions;
  // Stage 6 (empty without a detector): the blobs whose class the detector's palette names,
  // colour = palette label; detection blob indices refer to these. detector_blob_source[i] is
  // the index into `blobs` of detector_blobs[i].
  std::vector<detect::Blob> detector_blobs;
  std::vector<int> detector_blob_source;
  std::vector<detect::Detection> detections;
  // Every missing-patch fit of the detector, with what the frame shows at its missing patch
  // (MissingPatchLook); the rejected ones are not in `detections`.
  std::vector<MissingPatchLook> missing_patch_looks;
  // With FrameDetectorOptions::explain: why each key candidate became a detection or not; key
  // blob indices refer to detector_blobs.
  std::vector<detect::KeyExplanation> explanations;
  // With FrameDetectorOptions::explain: one detect::KeyDiagnosis per explanation (same order):
  // the measures against their bounds, the nearest rotation, and the cheapest setting change
  // (in the settings file's terms) that the detector confirms accepts the robot.
  std::vector<detect::KeyDiagnosis> diagnoses;
  VisionStats vision_stats;
  detect::DetectStats detect_stats;
  // With FrameDetectorOptions::collect_timing: this frame's stage times under kFrameStageNames,
  // and stage 6's own stages under detect::kDetectStageNames. Sum frames with +=.
  TimeProfile profile;
  TimeProfile detect_profile;
};

class FrameDetector {
 public:
  // `detector`: the patterns to detect, or nullopt for blobs only. Throws InputError for a bad
  // configuration (options, thresholds against calibration heights, detector settings).
  FrameDetector(Thresholds thresholds, camera::Calibration calibration,
                std::optional<detect::DetectorConfig> detector, FrameDetectorOptions options);
  ~FrameDetector();
  FrameDetector(FrameDetector&&) noexcept;
  FrameDetector& operator=(FrameDetector&&) noexcept;

  // Stages 1-6 on a frame file (ReadFrameFile with the options' raw size); InputError for a bad
  // file or a frame whose size differs from the calibration's.
  const FrameResult& DetectFile(const std::string& path);
  // Stages 2-6 on a frame in memory, read where it is (an Image, or a view of any strides: no
  // copy is made; only the debug images copy it); `name` stands for it in messages, results and
  // debug images.
  const FrameResult& Detect(const camera::ImageView& image, const std::string& name);

  // Mismatches between the thresholds' class names and the detector's palette, found at
  // construction, for the caller to show: a class no palette colour names (its blobs never reach
  // the detector) and a colour a pattern uses that no class names (no blob can have it -- e.g.
  // a class "magenta" for the palette's "pink" drops every pink-dotted robot).
  const std::vector<std::string>& warnings() const { return warnings_; }

  bool has_detector() const { return detector_.has_value(); }
  const detect::Detector& detector() const { return *detector_; }  // has_detector() only
  // The pipeline segments with the calibration of the frames as binned; frame_calibration()
  // is the frames' own (the same without binning).
  const VisionPipeline& pipeline() const { return pipeline_; }
  const camera::Calibration& frame_calibration() const { return frame_calibration_; }
  const FrameDetectorOptions& options() const { return options_; }

 private:
  void Process(const camera::ImageView& image, const std::string& name);
  void RunStages(const camera::ImageView& image);
  void WriteDebugImages(const camera::ImageView& image) const;
  void LookAtMissingPatches();
  MissingPatchLook LookAt(const detect::Detection& d) const;

  FrameDetectorOptions options_;
  camera::Calibration frame_calibration_;  // the frames' own; the pipeline's is binned
  VisionPipeline pipeline_;
  std::optional<detect::Detector> detector_;
  camera::Image binned_;  // the frame binned (options_.binning)
  camera::Image lit_;     // the frame scaled to the thresholds' light (options_.light_luma)
  std::vector<int> palette_label_;  // class index -> detector palette label, or -1
  // [pattern][patch]: bit L set when the patch may have palette colour L (MissingPatchLook::own).
  std::vector<std::vector<uint64_t>> patch_colours_;
  std::vector<int> kept_;  // detection index -> index after the missing-patch check, or -1
  std::vector<std::string> warnings_;
  // The detector's area_ratio_min over the settings' (AdaptToCamera's edge-loss factor).
  double area_ratio_min_scale_ = 1.0;
  FrameResult result_;
};

// The warnings of FrameDetector::warnings() for these thresholds and detector configuration.
std::vector<std::string> PaletteWarnings(const Thresholds& thresholds,
                                         const detect::DetectorConfig& config);

// The explanations of `result` as text for people, one line per key candidate:
//   <frame>: key <blob> <colour> at (<u>, <v>) px, (<x>, <y>) mm, <pattern>: <outcome and why>
std::string ExplanationText(const FrameResult& result, const FrameDetector& frames);

}  // namespace patlab::vision

#include "patlab/vision/frame_detector.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/made_folders.h"
#include "patlab/render/draw.h"
#include "patlab/vision/debug_image.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {

namespace fs = std::filesystem;

std::vector<OptionsProblem> Check(const FrameDetectorOptions& o) {
  std::vector<OptionsProblem> problems = Check(o.segmenter);
  const bool no_raw = o.raw_width_px == 0 && o.raw_height_px == 0;
  const bool raw_ok = o.raw_width_px > 0 && o.raw_width_px % 2 == 0 && o.raw_height_px > 0;
  if (!no_raw && !raw_ok) {
    problems.push_back({"raw_size", "raw frame size " + std::to_string(o.raw_width_px) + "x" +
                                        std::to_string(o.raw_height_px) +
                                        "; expected a positive even width and a positive height"});
  }
  for (OptionsProblem& problem : detect::Check(detect::FrameSettings{
           o.edge_loss_px,
           {},
           o.light_luma != 0.0 ? std::optional<double>(o.light_luma) : std::nullopt,
           o.binning})) {
    problems.push_back(std::move(problem));
  }
  return problems;
}

void Validate(const FrameDetectorOptions& options) { ThrowFirstProblem(Check(options)); }

Region InFramePixels(const Region& binned, int k) {
  Region r = binned;
  r.area_px = binned.area_px * k * k;
  r.x_min = binned.x_min * k;
  r.y_min = binned.y_min * k;
  r.x_max = binned.x_max * k + k - 1;
  r.y_max = binned.y_max * k + k - 1;
  r.centroid_px = camera::ResizedPixel(binned.centroid_px, k);
  return r;
}

void ApplyFrameSettings(const detect::FrameSettings& settings, FrameDetectorOptions* options) {
  if (settings.edge_loss_px) options->edge_loss_px = *settings.edge_loss_px;
  if (settings.missing_patch) options->missing_patch = settings.missing_patch;
  if (settings.light_luma) options->light_luma = *settings.light_luma;
  if (settings.binning) options->binning = static_cast<int>(*settings.binning);
}

double FrameLight(const camera::ImageView& image) {
  std::array<long, 256> histogram{};
  long n = 0;
  for (int y = 0; y < image.height_px; y += 4) {
    const uint8_t* row = image.Row(y);
    for (int x = 0; x < image.width_px; x += 4) {
      const uint8_t* p = row + x * image.pixel_stride;
      int luma = 0;
      if (image.format == camera::PixelFormat::kUyvy) {
        luma = p[image.channel_stride];  // U Y or V Y: the pixel's Y follows its chroma byte
      } else {
        int u = 0, v = 0;
        camera::RgbToYuv(p[0], p[image.channel_stride], p[2 * image.channel_stride], &luma, &u, &v);
      }
      ++histogram[static_cast<size_t>(luma)], ++n;
    }
  }
  long seen = 0;
  for (int v = 0; v < 256; ++v) {
    seen += histogram[static_cast<size_t>(v)];
    if (2 * seen >= n) return std::max(v, 1);
  }
  return 255;
}

namespace {

// The frame as RGB with every channel scaled by `gain` (clipped at 255), into `out`, whose buffer
// is reused: once it has held a frame of this size, scaling the next allocates nothing.
void ScaleToLight(const camera::ImageView& image, double gain, camera::Image* out) {
  camera::ToRgb(image, out);
  for (uint8_t& c : out->data) c = static_cast<uint8_t>(std::min(255.0, std::round(gain * c)));
}

// "6 detect" -> "6_detect": a stage name as a file name part.
std::string FileNamePart(std::string_view stage) {
  std::string out(stage);
  for (char& c : out) {
    if (c == ' ') c = '_';
  }
  return out;
}

// The colours the patterns use: key (team) colours, codebook ID colours and fixed colours.
std::vector<std::string> UsedColours(const detect::DetectorConfig& config) {
  std::vector<std::string> used;
  auto add = [&used](const std::string& c) {
    if (!c.empty() && std::find(used.begin(), used.end(), c) == used.end()) used.push_back(c);
  };
  for (const detect::DetectorPattern& p : config.patterns) {
    for (const std::string& c : p.key_colours) add(c);
    for (const std::string& c : p.codebook.colours) add(c);
    for (const Patch& patch : p.pattern.patches) {
      if (patch.role == PatchRole::kFixed) add(patch.colour);
    }
  }
  return used;
}

}  // namespace

std::vector<std::string> PaletteWarnings(const Thresholds& thresholds,
                                         const detect::DetectorConfig& config) {
  std::vector<std::string> warnings;
  const auto& palette = config.palette;
  for (const ColorClass& c : thresholds.classes) {
    if (std::find(palette.begin(), palette.end(), c.name) != palette.end()) continue;
    warnings.push_back(thresholds.source + ": class \"" + EscapeForMessage(c.name) +
                       "\" is no colour of the detector's palette; its blobs are not shown to the "
                       "detector");
  }
  for (const std::string& colour : UsedColours(config)) {
    if (thresholds.Find(colour) >= 0) continue;
    warnings.push_back("detector colour \"" + EscapeForMessage(colour) +
                       "\" is used by a pattern but no class of " + thresholds.source +
                       " has that name; no blob can have it, so patterns needing it are not "
                       "detected");
  }
  return warnings;
}

// The camera's mm per px on the plane at height_mm where the robots are: at the principal point
// of a pinhole camera, at the pixel of the world origin for plane homographies; 0 when it cannot
// be evaluated there.
double MmPerPx(const camera::CameraModel& camera, double height_mm) {
  std::optional<Vec2> pixel;
  if (camera.is_pinhole()) {
    pixel = Vec2(camera.pinhole().cx_px, camera.pinhole().cy_px);
  } else {
    pixel = camera.WorldToPixel(Vec2::Zero(), height_mm);
  }
  if (!pixel) return 0.0;
  return std::sqrt(std::max(camera.AreaScale(*pixel, height_mm), 0.0));
}

// The smallest fraction of a patch's area left when a rim of edge_mm is taken off all around,
// over every patch of the enabled patterns.
double EdgeLossFactor(const detect::DetectorConfig& config, double edge_mm) {
  double factor = 1.0;
  for (const detect::DetectorPattern& p : config.patterns) {
    for (const Patch& patch : p.pattern.patches) {
      double shrunk = 0.0;
      if (patch.shape == PatchShape::kRectangle) {
        shrunk = std::max(patch.size_mm.x() - 2.0 * edge_mm, 0.0) *
                 std::max(patch.size_mm.y() - 2.0 * edge_mm, 0.0);
      } else {
        const double r = std::max(patch.radius_mm - edge_mm, 0.0);
        shrunk = std::numbers::pi * r * r;
      }
      factor = std::min(factor, shrunk / patch.Area());
    }
  }
  return factor;
}

std::vector<std::string> DebugImageNames(const std::string& stem, bool with_detections) {
  std::vector<std::string> names;
  for (int stage : {1, 3, 4, 5}) {  // kFrameStageNames index: stages 2, 4, 5 and 6
    if (stage == 5 && !with_detections) continue;
    names.push_back(stem + "." + FileNamePart(kFrameStageNames[stage]) + ".png");
  }
  return names;
}

void AdaptToCamera(detect::DetectorConfig& config, const camera::Calibration& calibration,
                   double edge_loss_px) {
  // The calibration's recorded residual on the robot-top plane (default height) widens the
  // detector's geometric tolerance (detect::DetectorOptions::calibration_residual_mm).
  config.options.calibration_residual_mm = calibration.ResidualRmsMm(calibration.default_height_mm);
  // The lower area bound of a patch whose rim the segmentation loses (FrameDetectorOptions::
  // edge_loss_px): area_ratio_min of the shrunk patch, i.e. area_ratio_min times the smallest
  // shrunk fraction over the patterns' patches.
  const double edge_mm = edge_loss_px * MmPerPx(calibration.camera, calibration.default_height_mm);
  config.options.area_ratio_min *= EdgeLossFactor(config, edge_mm);
}

FrameDetector::FrameDetector(Thresholds thresholds, camera::Calibration calibration,
                             std::optional<detect::DetectorConfig> detector,
                             FrameDetectorOptions options)
    : options_((Validate(options), std::move(options))),
      frame_calibration_(std::move(calibration)),
      pipeline_(std::move(thresholds),
                options_.binning == 1 ? frame_calibration_
                                      : frame_calibration_.Resized(
                                            1.0 / options_.binning,
                                            frame_calibration_.image_width_px / options_.binning,
                                            frame_calibration_.image_height_px / options_.binning),
                options_.segmenter) {
  result_.profile = TimeProfile(options_.collect_timing);
  result_.detect_profile = TimeProfile(options_.collect_timing);
  if (!detector) return;
  // The calibration's recorded residual on the robot-top plane (default height) widens the
  // detector's geometric tolerance (detect::DetectorOptions::calibration_residual_mm).
  const double file_area_ratio_min = detector->options.area_ratio_min;
  AdaptToCamera(*detector, pipeline_.calibration(), options_.edge_loss_px);
  if (file_area_ratio_min > 0.0) {
    area_ratio_min_scale_ = detector->options.area_ratio_min / file_area_ratio_min;
  }
  if (options_.missing_patch) detector->options.missing_patch = *options_.missing_patch;
  detector_.emplace(std::move(*detector));
  for (const ColorClass& c : pipeline_.thresholds().classes) {
    palette_label_.push_back(detector_->ColourLabel(c.name));
  }
  // The colours each patch may have, as palette bits, for MissingPatchLook::own.
  const auto bits = [this](const std::vector<std::string>& names) {
    uint64_t mask = 0;
    for (const std::string& name : names) {
      const int label = detector_->ColourLabel(name);
      if (label >= 0) mask |= uint64_t{1} << label;
    }
    return mask;
  };
  for (const detect::DetectorPattern& p : detector_->config().patterns) {
    std::vector<uint64_t>& masks = patch_colours_.emplace_back();
    for (const Patch& patch : p.pattern.patches) {
      masks.push_back(patch.role == PatchRole::kKey  ? bits(p.key_colours)
                      : patch.role == PatchRole::kId ? bits(p.codebook.colours)
                                                     : bits({patch.colour}));
    }
  }
  warnings_ = PaletteWarnings(pipeline_.thresholds(), detector_->config());
}

FrameDetector::~FrameDetector() = default;
FrameDetector::FrameDetector(FrameDetector&&) noexcept = default;
FrameDetector& FrameDetector::operator=(FrameDetector&&) noexcept = default;

const FrameResult& FrameDetector::DetectFile(const std::string& path) {
  TimeProfile& profile = result_.profile;
  profile.Clear();
  profile.Start();
  // The size the header states, against the pixel budget and the calibration, before any pixel
  // is decoded or allocated.
  if (const std::optional<FrameHeaderSize> size =
          ReadFrameHeaderSize(path, options_.raw_width_px, options_.raw_height_px)) {
    CheckFrameSize(frame_calibration_, size->width_px, size->height_px, path);
  }
  const camera::Image image = ReadFrameFile(path, options_.raw_width_px, options_.raw_height_px);
  profile.Stamp(kFrameStageNames[0]);
  Process(image, path);
  return result_;
}

const FrameResult& FrameDetector::Detect(const camera::ImageView& image, const std::string& name) {
  result_.profile.Clear();
  Process(image, name);
  return result_;
}

void FrameDetector::Process(const camera::ImageView& image, const std::string& name) {
  result_.frame = name;
  CheckFrameSize(frame_calibration_, image.width_px, image.height_px, name);
  camera::ImageView frame = image;
  if (options_.binning > 1) {
    camera::BinImage(image, options_.binning, &binned_);
    frame = binned_;
  }
  camera::ImageView classified = frame;
  if (options_.light_luma > 0.0) {
    const double gain = options_.light_luma / FrameLight(frame);
    if (std::abs(gain - 1.0) > kLightTolerance) {
      ScaleToLight(frame, gain, &lit_);
      classified = lit_;
    }
  }
  RunStages(classified);
  if (!options_.debug_dir.empty()) WriteDebugImages(classified);
  // The debug images show the frame as worked on; the results give the frame's own pixels.
  if (options_.binning > 1) {
    for (Region& region : result_.blob_regions) region = InFramePixels(region, options_.binning);
  }
}

// Stages 2-5 (the pipeline) and 6: the blobs whose class is in the detector's palette, relabelled
// with their palette label, through the detector.
void FrameDetector::RunStages(const camera::ImageView& image) {
  FrameResult& r = result_;
  r.detect_profile.Clear();
  pipeline_.Process(image, &r.blobs, &r.vision_stats, &r.profile);
  r.blob_regions.clear();
  for (int region : pipeline_.blob_region()) {
    r.blob_regions.push_back(pipeline_.segmenter().regions()[static_cast<size_t>(region)]);
  }
  r.detector_blobs.clear();
  r.detector_blob_source.clear();
  r.detections.clear();
  r.explanations.clear();
  r.diagnoses.clear();
  r.detect_stats = detect::DetectStats{};
  if (!detector_) return;
  r.profile.Start();
  for (size_t i = 0; i < r.blobs.size(); ++i) {
    const detect::Blob& b = r.blobs[i];
    const int label = palette_label_[static_cast<size_t>(b.colour)];
    if (label < 0) continue;
    r.detector_blobs.push_back(detect::Blob{b.position_mm, label, b.area_mm2});
    r.detector_blob_source.push_back(static_cast<int>(i));
  }
  detector_->Detect(r.detector_blobs, &r.detections, &r.detect_stats, &r.detect_profile,
                    options_.explain ? &r.explanations : nullptr);
  LookAtMissingPatches();
  if (options_.explain) {
    r.diagnoses = detect::DiagnoseKeys(detector_->config(), r.detector_blobs, r.explanations,
                                       {.area_ratio_min_scale = area_ratio_min_scale_});
  }
  r.profile.Stamp(kFrameStageNames[5]);
}

// The footprint of detection d's missing patch: the patch shape at the fitted pose on the
// robot-top plane, the pixels whose centres map inside it, counted by class (MissingPatchLook).
MissingPatchLook FrameDetector::LookAt(const detect::Detection& d) const {
  MissingPatchLook look;
  look.detection = d;
  const detect::DetectorPattern& dp = detector_->config().patterns[static_cast<size_t>(d.pattern)];
  look.key_blob = d.blob[static_cast<size_t>(dp.pattern.key_index)];
  const Patch& patch = dp.pattern.patches[static_cast<size_t>(d.missing_patch)];
  const uint64_t own =
      patch_colours_[static_cast<size_t>(d.pattern)][static_cast<size_t>(d.missing_patch)];
  const camera::Calibration& calibration = pipeline_.calibration();
  const double height = calibration.default_height_mm;
  const Segmenter& segmenter = pipeline_.segmenter();
  // The pixel box of the patch's bounding disc (its four extreme points, 1 px margin).
  const Vec2 centre = d.pose.Apply(patch.position_mm);
  const double reach = patch.BoundingRadius();
  double u0 = segmenter.width_px(), v0 = segmenter.height_px(), u1 = -1.0, v1 = -1.0;
  for (const Vec2& offset : {Vec2(reach, 0), Vec2(-reach, 0), Vec2(0, reach), Vec2(0, -reach)}) {
    const auto px = calibration.camera.WorldToPixel(centre + offset, height);
    if (!px) return look;
    u0 = std::min(u0, px->x()), u1 = std::max(u1, px->x());
    v0 = std::min(v0, px->y()), v1 = std::max(v1, px->y());
  }
  const int ulo = std::max(static_cast<int>(std::floor(u0)) - 1, 0);
  const int uhi = std::min(static_cast<int>(std::ceil(u1)) + 1, segmenter.width_px() - 1);
  const int vlo = std::max(static_cast<int>(std::floor(v0)) - 1, 0);
  const int vhi = std::min(static_cast<int>(std::ceil(v1)) + 1, segmenter.height_px() - 1);
  const double c = std::cos(d.pose.theta_rad), s = std::sin(d.pose.theta_rad);
  for (int v = vlo; v <= vhi; ++v) {
    for (int u = ulo; u <= uhi; ++u) {
      const auto world = calibration.camera.PixelToWorld(Vec2(u, v), height);
      if (!world) continue;
      const Vec2 w = *world - Vec2(d.pose.x_mm, d.pose.y_mm);
      if (!patch.Contains(Vec2(c * w.x() + s * w.y(), -s * w.x() + c * w.y()))) continue;
      ++look.pixels;
      const int cls = segmenter.class_image()[static_cast<size_t>(v) * segmenter.width_px() + u];
      const int label = cls > 0 ? palette_label_[static_cast<size_t>(cls - 1)] : -1;
      if (label < 0) continue;
      ++((own >> label) & 1U ? look.own : look.other);
    }
  }
  look.rejected = look.other > kMissingPatchOtherMax * look.pixels;
  return look;
}

// Every missing-patch fit gets its MissingPatchLook; those whose missing patch shows clearly
// another colour leave the detections (the explanations' detection indices follow).
void FrameDetector::LookAtMissingPatches() {
  FrameResult& r = result_;
  r.missing_patch_looks.clear();
  kept_.clear();
  size_t kept = 0;
  for (size_t i = 0; i < r.detections.size(); ++i) {
    const detect::Detection& d = r.detections[i];
    if (d.status == detect::DetectionStatus::kMissingPatch && d.missing_patch >= 0) {
      r.missing_patch_looks.push_back(LookAt(d));
      if (r.missing_patch_looks.back().rejected) {
        kept_.push_back(-1);
        continue;
      }
    }
    kept_.push_back(static_cast<int>(kept));
    r.detections[kept++] = r.detections[i];
  }
  if (kept == r.detections.size()) return;
  r.detections.resize(kept);
  for (detect::KeyExplanation& e : r.explanations) {
    if (e.detection >= 0) e.detection = kept_[static_cast<size_t>(e.detection)];
  }
}

namespace {

// Detections on the debug image: drawn at the key blob's plane height; the heading is the model
// x axis, 100 mm long; the circle passes 90 mm from the centre.
void DrawDetections(const FrameResult& r, const VisionPipeline& pipeline,
                    const detect::Detector& detector, camera::Image* debug) {
  const camera::Calibration& calibration = pipeline.calibration();
  for (const detect::Detection& d : r.detections) {
    const int key = d.blob[static_cast<size_t>(
        detector.config().patterns[static_cast<size_t>(d.pattern)].pattern.key_index)];
    const double height =
        key >= 0
            ? pipeline.class_height_mm(
                  r.blobs[static_cast<size_t>(r.detector_blob_source[static_cast<size_t>(key)])]
                      .colour)
            : calibration.default_height_mm;
    const auto centre = calibration.camera.WorldToPixel(Vec2(d.pose.x_mm, d.pose.y_mm), height);
    const auto tip = calibration.camera.WorldToPixel(d.pose.Apply(Vec2(100, 0)), height);
    const auto rim = calibration.camera.WorldToPixel(d.pose.Apply(Vec2(0, 90)), height);
    if (!centre || !tip || !rim) continue;
    const std::string label = d.id >= 0 ? std::to_string(d.id) : "?";
    render::DrawDetection(debug, *centre, (*rim - *centre).norm(), *tip, label, {255, 255, 255});
  }
}

// The letter marking a key candidate's outcome on the debug image (frame_detector.h).
const char* OutcomeLetter(detect::KeyOutcome outcome) {
  switch (outcome) {
    case detect::KeyOutcome::kKeyArea:
      return "A";
    case detect::KeyOutcome::kFewNeighbours:
      return "N";
    case detect::KeyOutcome::kGeometry:
      return "G";
    case detect::KeyOutcome::kColours:
      return "C";
    case detect::KeyOutcome::kConflict:
      return "X";
    case detect::KeyOutcome::kDetected:
      break;
  }
  return "";
}

// Explain: every key candidate that is no detection, a red ring round its key region and the
// letter of its outcome.
void DrawMisses(const FrameResult& r, camera::Image* debug) {
  for (const detect::KeyExplanation& e : r.explanations) {
    const bool rejected = e.outcome == detect::KeyOutcome::kDetected && e.detection < 0;
    if (e.outcome == detect::KeyOutcome::kDetected && !rejected) continue;
    const Region& region = r.blob_regions[static_cast<size_t>(
        r.detector_blob_source[static_cast<size_t>(e.key_blob)])];
    const double radius = std::sqrt(region.area_px / std::numbers::pi) + 4.0;
    render::DrawDetection(debug, region.centroid_px, radius, region.centroid_px,
                          rejected ? "M" : OutcomeLetter(e.outcome), {255, 40, 40});
  }
}

// The blobs the next stage sees: with a detector, those in its palette; discs of the region's
// area at its centroid, in the class colour, on the dimmed frame.
camera::Image DrawBlobs(const camera::ImageView& frame, const FrameResult& r,
                        const Thresholds& thresholds, bool detector_blobs_only) {
  camera::Image out = camera::ToRgb(frame);
  for (uint8_t& v : out.data) v = static_cast<uint8_t>(v / 3);
  const size_t count = detector_blobs_only ? r.detector_blob_source.size() : r.blobs.size();
  for (size_t k = 0; k < count; ++k) {
    const size_t i = detector_blobs_only ? static_cast<size_t>(r.detector_blob_source[k]) : k;
    const Region& region = r.blob_regions[i];
    render::DrawDisc(&out, region.centroid_px, std::sqrt(region.area_px / std::numbers::pi),
                     thresholds.classes[static_cast<size_t>(r.blobs[i].colour)].display_rgb);
  }
  return out;
}

}  // namespace

void FrameDetector::WriteDebugImages(const camera::ImageView& image) const {
  const Thresholds& thresholds = pipeline_.thresholds();
  const std::vector<std::string> names =
      DebugImageNames(fs::path(result_.frame).stem().string(), has_detector());
  const fs::path dir(options_.debug_dir);
  // Made like `mkdir -p`, and removed again if the first image cannot be written
  // (io/made_folders.h).
  io::MadeFolders made({dir.string()});
  if (const std::error_code error = made.Make(dir.string())) {
    throw InputError(options_.debug_dir + ": cannot create the debug directory (" +
                     error.message() + "); expected a writable directory");
  }
  WritePng(DrawClasses(pipeline_.segmenter(), thresholds), (dir / names[0]).string());
  made.Keep();
  camera::Image regions = DrawRegions(image, pipeline_.segmenter(), thresholds);
  WritePng(regions, (dir / names[1]).string());
  WritePng(DrawBlobs(image, result_, thresholds, has_detector()), (dir / names[2]).string());
  if (!has_detector()) return;
  DrawDetections(result_, pipeline_, *detector_, &regions);
  DrawMisses(result_, &regions);
  WritePng(regions, (dir / names[3]).string());
}

}  // namespace patlab::vision

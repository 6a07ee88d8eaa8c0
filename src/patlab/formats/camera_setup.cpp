// A new camera set up from its frames (camera_setup.h): calibration, thresholds, tolerances.
#include "patlab/formats/camera_setup.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "patlab/calib/calibrate.h"
#include "patlab/core/colour_names.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup_internal.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/toml_util.h"
#include "patlab/vision/field_lines.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/thresholds_auto.h"
#include "patlab/vision/thresholds_fit.h"

namespace patlab::formats {
namespace {

namespace fs = std::filesystem;

// The input's checks; the binning the frames are worked on at (SetupOptions::binning resolved).
int CheckSetupInput(const std::vector<const camera::Image*>& frames,
                    const std::vector<std::string>& names, const SetupOptions& o) {
  if (frames.empty() || frames.size() != names.size())
    throw InputError("no frames; expected at least one FRAME of the camera");
  if (o.fields.empty()) throw InputError("--field names no model; expected a model or a family");
  if (o.settings_path.empty())
    throw InputError("missing --settings S; expected detector settings naming the patterns");
  if (!(o.robot_height_mm >= 0.0 && o.robot_height_mm <= 1000.0)) {
    throw InputError("--robot-height is " + FormatNumber(o.robot_height_mm) +
                     " mm; expected 0 to 1000");
  }
  if (o.camera_height_mm && !(*o.camera_height_mm > o.robot_height_mm &&
                              *o.camera_height_mm <= camera::kMaxCameraHeightMm)) {
    throw InputError("--camera-height is " + FormatNumber(*o.camera_height_mm) +
                     " mm; expected above the robots' height (" + FormatNumber(o.robot_height_mm) +
                     " mm) and at most " + FormatNumber(camera::kMaxCameraHeightMm) + " mm");
  }
  if (!o.landmarks.empty() && o.landmarks.size() < 4) {
    throw InputError("--landmark given " + std::to_string(o.landmarks.size()) +
                     " times; expected at least 4 landmarks (or none: the lines decide)");
  }
  if (o.binning < 0 || o.binning > detect::kMaxBinning) {
    throw InputError("--binning is " + std::to_string(o.binning) + "; expected 0 (chosen from " +
                     "the frames' size) to " + std::to_string(detect::kMaxBinning));
  }
  for (size_t i = 1; i < frames.size(); ++i) {
    const camera::Image* frame = frames[i];
    if (frame->width_px != frames.front()->width_px ||
        frame->height_px != frames.front()->height_px) {
      throw InputError(names[i] + ": image is " + std::to_string(frame->width_px) + "x" +
                       std::to_string(frame->height_px) + "; expected the first frame's size, " +
                       std::to_string(frames.front()->width_px) + "x" +
                       std::to_string(frames.front()->height_px) + " (frames of one camera)");
    }
  }
  const int binning =
      o.binning > 0 ? o.binning : SetupBinning(frames.front()->width_px, frames.front()->height_px);
  if (frames.front()->width_px / binning < 64 || frames.front()->height_px / binning < 64) {
    throw InputError(names.front() + ": image is " + std::to_string(frames.front()->width_px) +
                     "x" + std::to_string(frames.front()->height_px) + ", binned " +
                     std::to_string(binning) + " x " + std::to_string(binning) +
                     " too small to find a field in; expected at least 64 x 64 px after binning");
  }
  Validate(o.thresholds);
  Validate(o.colours);
  return binning;
}

// The first frame's lines: the line pixels found once, every field model screened, the best few
// fitted, the best kept, with the cameras the lines do not decide from it (its rivals).
calib::FamilyCalibration CalibrateFamily(const camera::Image& frame, const std::string& name,
                                         const std::vector<calib::LinePixel>& pixels,
                                         const SetupOptions& o) {
  calib::FamilyOptions family;
  family.keep_rivals = true;
  // Up to six rivals weighed by their robots: fresh rendered seed 146's lines fit seven cameras
  // within 10 %, the true one sixth, and no robot decodes through the best four. A rival costs
  // little beside the search (seed 146: 8.4 s of CPU with three rivals, 8.8 s with six).
  family.max_rivals = 6;
  // The lines' narrow runners-up, weighed by the robots where none decodes through the cameras
  // the lines left (internal::WeighCameras); the share is the screen's, below which no model is
  // fitted.
  family.runner_up_ratio = family.screen_ratio;
  calib::AutoOptions options;
  options.camera_height_mm = o.camera_height_mm;
  try {
    return calib::AutoCalibrateFamily(pixels, frame.width_px, frame.height_px, name, o.fields,
                                      options, family, o.lenders);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) +
                     "; or give four --landmark NAME=X,Y (patlab setup --list-landmarks FIELD)");
  }
}

// The models tried, best first: fitted ones by their score, then the others by their screen.
void TriedOf(const calib::FamilyCalibration& family, SetupResult* r) {
  for (const calib::FamilyTry& t : family.tries) {
    r->tried.push_back({t.field, t.score_px, t.held_out_mapping_mm, t.failure, t.screen_px,
                        t.fitted, t.same_as, t.screen_view_of});
  }
  std::stable_sort(r->tried.begin(), r->tried.end(),
                   [](const SetupFieldTry& a, const SetupFieldTry& b) {
                     if (a.failure.empty() != b.failure.empty()) return a.failure.empty();
                     if (a.failure.empty()) return a.score_px > b.score_px;
                     return std::isfinite(a.screen_px) &&
                            (!std::isfinite(b.screen_px) || a.screen_px > b.screen_px);
                   });
}

// The calibration from clicked landmarks of the first field model.
void CalibrateFromLandmarks(const camera::Image& frame, const std::string& name,
                            const SetupOptions& o, SetupResult* r) {
  const calib::Field& field = o.fields.front();
  calib::CalibrationInput in;
  in.source = name;
  in.loc = FileLoc{name, 0};
  in.image_width_px = frame.width_px;
  in.image_height_px = frame.height_px;
  for (const SetupLandmark& l : o.landmarks) {
    const calib::FieldPoint* p = field.FindPoint(l.name);
    if (p == nullptr) {
      throw InputError("--landmark " + l.name + ": not a landmark of " + field.name +
                       "; expected one of " + field.PointNames());
    }
    in.points.push_back({l.name, l.pixel, p->at_mm, 0.0, in.loc});
  }
  in.options.holdout_folds = std::min<int>(5, static_cast<int>(o.landmarks.size()));
  in.options.camera_height_mm = o.camera_height_mm;
  r->field = field;
  r->from_landmarks = true;
  r->calibration_input = in;
  r->calibration_fit = calib::FitCamera(in);
  r->mapping_error_mm = r->calibration_fit.heldout_rms_mm;
  r->calibration_report = calib::FitReportText(in, r->calibration_fit);
  r->tried.push_back({field.name, 0.0, r->mapping_error_mm, "", 0.0, true, "", ""});
}

// The settings' text with relative pattern, codebook and patterns_dir paths made absolute (the
// settings are written into another folder), its [detector] table replaced by `t`: the
// tolerances setup chose, and the settings' own policies (missing_patch, max_neighbours, the
// estimator), which say how the user wants robots read, not how far this camera's blobs stray;
// and its [frame] light_luma set to the light the thresholds are fitted at.
std::string SettingsText(const std::string& path, const detect::DetectorOptions& t,
                         double light_luma, const std::string& comment) {
  const std::string text = io::ReadTextFile(path, "detector settings");
  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  static const std::regex kPath(R"(^(\s*(pattern|codebook|patterns_dir)\s*=\s*")([^"]+)(".*)$)");
  static const std::regex kTable(R"(^\s*\[.*)");
  static const std::regex kFrame(R"(^\s*\[\s*frame\s*\].*)");
  // setup writes the light and the binning of the frames it worked on: the given file's go.
  static const std::regex kLight(R"(^\s*(light_luma|binning)\s*=.*)");
  const std::string light_line = "light_luma = " + FormatRoundTrip(light_luma) +
                                 "  # the frames' light the thresholds are fitted at\n";
  std::istringstream in(text);
  std::string out = comment, line;
  bool in_detector = false, in_frame = false, frame_seen = false;
  while (std::getline(in, line)) {
    if (std::regex_match(line, kTable)) {
      in_detector = line.find("[detector]") != std::string::npos;
      in_frame = std::regex_match(line, kFrame);
      if (in_frame) {
        out += line + "\n" + light_line;
        frame_seen = true;
        continue;
      }
    }
    if (in_detector || (in_frame && std::regex_match(line, kLight))) continue;
    std::smatch m;
    // A pattern or codebook named without a folder or ".toml" is looked up in patterns_dir.
    const bool is_path =
        std::regex_match(line, m, kPath) &&
        (m[2].str() == "patterns_dir" || m[3].str().find('/') != std::string::npos ||
         m[3].str().ends_with(".toml"));
    if (is_path && !fs::path(m[3].str()).is_absolute()) {
      line = m[1].str() + (base / m[3].str()).lexically_normal().string() + m[4].str();
    }
    out += line + "\n";
  }
  if (!frame_seen) out += "\n[frame]\n" + light_line;
  out += "\n[detector]\npatch_sigma_mm = " + FormatRoundTrip(t.patch_sigma_mm) +
         "\ngeometry_confidence = " + FormatRoundTrip(t.geometry_confidence) +
         "\nreach_margin_mm = " + FormatRoundTrip(t.reach_margin_mm) +
         "\narea_ratio_min = " + FormatRoundTrip(t.area_ratio_min) +
         "\narea_ratio_max = " + FormatRoundTrip(t.area_ratio_max) + "\nmissing_patch = \"" +
         std::string(detect::MissingPatchPolicyName(t.missing_patch)) +
         "\"\nmax_neighbours = " + std::to_string(t.max_neighbours) + "\nestimator = \"" +
         std::string(estimate::EstimatorName(t.estimator)) +
         "\"\nml_max_iterations = " + std::to_string(t.ml.max_iterations) + "\n";
  return out;
}

double SmallestPatchMm(const detect::DetectorConfig& config) {
  double r = INFINITY;
  for (const detect::DetectorPattern& p : config.patterns)
    for (const Patch& patch : p.pattern.patches) r = std::min(r, patch.radius_mm);
  return std::isfinite(r) ? r : 0.0;
}

// ", box widened towards the noise by Y +a, U +b, V +c levels" for a class whose box the blob fit
// widened (vision::AutoClassFit::widened_levels), else nothing.
std::string WidenedText(const std::array<int, 3>& levels) {
  if (levels == std::array<int, 3>{}) return "";
  return ", box widened towards the noise by Y +" + std::to_string(levels[0]) + ", U +" +
         std::to_string(levels[1]) + ", V +" + std::to_string(levels[2]) + " levels";
}

// ", N px of regions too narrow for a blob spared" for a class whose box the blob fit did not
// pull in against its colour's patches too narrow for a blob (vision::AutoClassFit::thin_alike),
// else nothing.
std::string ThinAlikeText(long pixels) {
  if (pixels == 0) return "";
  return ", " + std::to_string(pixels) + " px of regions too narrow for a blob spared";
}

// The models tried, one line each: the fitted ones' scores, why the others were dropped.
std::string TriedText(const std::vector<SetupFieldTry>& tried) {
  int fitted = 0;
  for (const SetupFieldTry& t : tried) fitted += t.fitted && t.same_as.empty() ? 1 : 0;
  std::string s = "  (" + std::to_string(tried.size()) +
                  " models screened by their search's best camera (px of line explained); " +
                  std::to_string(fitted) + " given the full fit)\n";
  for (const SetupFieldTry& t : tried) {
    s += "  " + t.field + ": ";
    if (t.failure.empty()) {
      s += FormatSignificant(t.score_px, 5) + " px of line explained (search " +
           FormatSignificant(t.screen_px, 5) + " px" +
           (t.screen_view_of.empty() ? "" : ", a view " + t.screen_view_of + "'s search found") +
           ")";
    } else {
      s += (!t.fitted && std::isfinite(t.screen_px) ? "" : "failed: ") + t.failure;
    }
    s += (t.same_as.empty() ? "" : " (the same lines as " + t.same_as + ")") + std::string("\n");
  }
  return s;
}

}  // namespace

detect::DetectorOptions SetupTolerances(const detect::DetectorOptions& base, double mm_per_px,
                                        double mapping_error_mm, double smallest_patch_px) {
  detect::DetectorOptions t = base;
  const double e = std::isfinite(mapping_error_mm) ? mapping_error_mm : 0.0;
  t.patch_sigma_mm = std::max(2.0, 0.4 * mm_per_px);
  t.reach_margin_mm = std::max(20.0, 3.0 * e + 2.0 * mm_per_px);
  const double r = smallest_patch_px;
  const double core = r > 1.06 ? (r - 1.06) / r : 0.0;
  t.area_ratio_min = std::clamp(0.5 * core * core, 0.1, 0.4);
  t.area_ratio_max = 2.5;
  return t;
}

void SetupBlobAreas(double smallest_patch_px, double largest_patch_px,
                    vision::BlobThresholdsOptions* options) {
  constexpr double kPi = 3.14159265358979323846;
  options->min_blob_area_px = std::max(3.0, 0.2 * kPi * smallest_patch_px * smallest_patch_px);
  options->min_blob_sigma_px = 0.3 * smallest_patch_px;
  options->max_blob_area_px =
      std::max(options->min_blob_area_px, 3.0 * kPi * largest_patch_px * largest_patch_px);
}

void internal::FinishSetup(const std::vector<const camera::Image*>& frames,
                           const std::vector<std::string>& names,
                           const detect::DetectorConfig& config, const SetupOptions& options,
                           SetupResult& r, bool fit_colours) {
  // A camera outside the model's range (a lens bent beyond any real one) would be written into a
  // calibration that `detect` refuses: it is refused here, with the numbers.
  if (const auto problems = camera::Check(r.calibration_fit.camera); !problems.empty()) {
    throw InputError(names.front() + ": the camera fitted to " + r.field.name + "'s " +
                     (r.from_landmarks ? "landmarks" : "lines") +
                     " leaves the camera model's range (" + problems.front().message +
                     "); expected a frame showing more of the field's lines, or give four "
                     "--landmark NAME=X,Y");
  }
  r.calibration_input.default_height_mm = options.robot_height_mm;
  const camera::CameraModel camera = camera::CameraModel::Pinhole(r.calibration_fit.camera);
  const camera::Image& first = *frames.front();
  r.mm_per_px = std::sqrt(camera.AreaScale(
      Vec2(0.5 * (first.width_px - 1), 0.5 * (first.height_px - 1)), options.robot_height_mm));
  r.smallest_patch_px = r.mm_per_px > 0.0 ? SmallestPatchMm(config) / r.mm_per_px : 0.0;
  const double error_bound = std::isfinite(r.mapping_resolution_mm)
                                 ? std::max(r.mapping_error_mm, r.mapping_resolution_mm)
                                 : r.mapping_error_mm;
  r.tolerances = SetupTolerances(config.options, r.mm_per_px, error_bound, r.smallest_patch_px);
  if (fit_colours) internal::FitColours(frames, config, options, &r);
  const std::string made =
      "# Made by patlab setup from " + names.front() + " (field " + r.field.name + ").\n";
  const std::string calibration_text =
      calib::CalibrationFileText(r.calibration_input, r.calibration_fit);
  double light = 0.0;
  for (const camera::Image* frame : frames) light += vision::FrameLight(*frame) / frames.size();
  const std::string settings_text = SettingsText(
      options.settings_path, r.tolerances, light,
      made + "# The detector settings " + options.settings_path +
          " with the tolerances setup chose ([detector]) and the frames' light ([frame] " +
          "light_luma, docs/setup.md).\n");
  if (fit_colours)
    internal::ChooseColourFit(frames, config, options, calibration_text, settings_text, &r);
  r.files = {{"calibration.toml", calibration_text},
             {"thresholds.toml",
              vision::ThresholdsToml(r.thresholds.thresholds,
                                     "Made by patlab setup from " + std::to_string(frames.size()) +
                                         " frame(s), the " + r.colour_fit + " colour fit.")},
             {"settings.toml", settings_text},
             {"setup.toml", made + "field = \"" + r.field.name +
                                "\"\ncalibration = \"calibration.toml\"\nthresholds = "
                                "\"thresholds.toml\"\nsettings = \"settings.toml\"\n"}};
}

namespace {

// The lines' camera, or, where they do not decide or no robot decodes through it, the one the
// robots choose (internal::WeighCameras); where the lines match too few marks or fit only at the
// focal length's bound with no robot decoding, the robots place the field (SetupFromRobots).
SetupResult SetupFromLines(const std::vector<const camera::Image*>& frames,
                           const std::vector<std::string>& names,
                           const detect::DetectorConfig& config, const SetupOptions& options) {
  vision::LineFinderOptions finder;
  finder.line_width_px = options.line_width_px;
  const std::vector<calib::LinePixel> pixels = vision::FindLinePixels(*frames.front(), finder);
  calib::FamilyCalibration family;
  try {
    family = CalibrateFamily(*frames.front(), names.front(), pixels, options);
  } catch (const InputError& e) {
    // A corner and a line: the robots' patterns may fix what the lines leave open.
    if (!internal::MatchedTooFewMarks(e.what())) throw;
    return internal::SetupFromRobots(frames, names, config, options, pixels, e.what());
  }
  std::string at_bound;
  SetupResult r = internal::WeighCameras(frames, names, config, options, family, &at_bound);
  if (!at_bound.empty())
    return internal::SetupFromRobots(frames, names, config, options, pixels, at_bound);
  TriedOf(family, &r);
  return r;
}

// The settings text with [frame] binning = k after its [frame] line (SettingsText writes one).
std::string WithBinning(const std::string& settings_text, int k) {
  static const std::regex kFrame(R"((^|\n)\s*\[\s*frame\s*\][^\n]*\n)");
  std::smatch m;
  PATLAB_CHECK(std::regex_search(settings_text, m, kFrame));
  const auto at = static_cast<size_t>(m.position(0) + m.length(0));
  return settings_text.substr(0, at) + "binning = " + std::to_string(k) +
         "  # the frames binned k x k, as setup worked on them\n" + settings_text.substr(at);
}

// The files of a setup that worked on frames binned k x k from width x height px, for the
// frames themselves: the calibration resized back to them (camera::CameraModel::Resized), the
// settings binning them as setup did.
void WriteForFrameSize(int width_px, int height_px, int k, SetupResult& r) {
  calib::CalibrationInput input = r.calibration_input;
  input.image_width_px = width_px;
  input.image_height_px = height_px;
  calib::CalibrationFit fit = r.calibration_fit;
  fit.camera = camera::CameraModel::Pinhole(fit.camera).Resized(k).pinhole();
  fit.rms_px *= k;
  fit.worst_px *= k;
  for (calib::PlaneResiduals& plane : fit.planes) {
    plane.rms_px *= k;
    plane.worst_px *= k;
  }
  for (auto& [name, text] : r.files) {
    if (name == "calibration.toml") text = calib::CalibrationFileText(input, fit);
    if (name == "settings.toml") text = WithBinning(text, k);
  }
}

}  // namespace

int SetupBinning(int width_px, int height_px) {
  const int longer = std::max(width_px, height_px);
  return std::clamp((longer + kSetupWorkingPx - 1) / kSetupWorkingPx, 1, detect::kMaxBinning);
}

SetupResult SetupCamera(const std::vector<const camera::Image*>& frames,
                        const std::vector<std::string>& names, const SetupOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  SetupOptions o = options;
  o.binning = CheckSetupInput(frames, names, options);
  const detect::DetectorConfig config = formats::LoadDetectorSettings(options.settings_path);
  const int width = frames.front()->width_px, height = frames.front()->height_px;
  std::vector<camera::Image> binned(o.binning > 1 ? frames.size() : 0);
  std::vector<const camera::Image*> working = frames;
  for (size_t i = 0; i < binned.size(); ++i) {
    camera::BinImage(*frames[i], o.binning, &binned[i]);
    working[i] = &binned[i];
  }
  for (SetupLandmark& l : o.landmarks)
    l.pixel = (l.pixel + Vec2(0.5, 0.5)) / o.binning - Vec2(0.5, 0.5);
  SetupResult r;
  if (o.landmarks.empty()) {
    r = SetupFromLines(working, names, config, o);
  } else {
    CalibrateFromLandmarks(*working.front(), names.front(), o, &r);
    internal::FinishSetup(working, names, config, o, r);
    internal::ChooseHeight(working, names, config, o, r);
  }
  r.binning = o.binning;
  r.frame_size_px = {width, height};
  if (o.binning > 1) WriteForFrameSize(width, height, o.binning, r);
  r.normalised_frames.reset();  // the frames are the caller's: no longer ours to point at
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::string SetupReportText(const SetupResult& r) {
  std::string s;
  if (r.binning > 1) {
    s += "frames binned " + std::to_string(r.binning) + " x " + std::to_string(r.binning) + ": " +
         std::to_string(r.frame_size_px[0]) + " x " + std::to_string(r.frame_size_px[1]) +
         " px worked on at " + std::to_string(r.frame_size_px[0] / r.binning) + " x " +
         std::to_string(r.frame_size_px[1] / r.binning) +
         " (pixel figures below are the binned frames'; calibration.toml maps the frames' own "
         "pixels, settings.toml's [frame] binning bins them for detect)\n";
  }
  s += "field model: " + r.field.name;
  if (r.few_lines.used) {
    s += internal::FewLinesText(r.few_lines);
  } else if (r.from_landmarks) {
    s += " (from " + std::to_string(r.calibration_input.points.size()) + " landmarks)\n";
  } else if (!r.undecided.empty()) {
    s += internal::UndecidedText(r) + TriedText(r.tried);
  } else if (r.tried.size() > 1) {
    const SetupFieldTry& second = r.tried[1];
    s += second.failure.empty()
             ? " (explains " + FormatSignificant(r.tried[0].score_px, 5) + " px of line; next " +
                   second.field + " " + FormatSignificant(second.score_px, 5) + " px, " +
                   FormatSignificant(r.tried[0].score_px - second.score_px, 4) + " px less)\n"
             : " (the only model of " + std::to_string(r.tried.size()) + " that fitted)\n";
    s += TriedText(r.tried);
  } else {
    s += "\n";
  }
  const bool below = r.mapping_error_mm < r.mapping_resolution_mm;
  s += "mapping error: " +
       (below ? "below " + FormatSignificant(r.mapping_resolution_mm, 2) +
                    " mm (the line finder's resolution; estimate " +
                    FormatSignificant(r.mapping_error_mm, 2) + " mm)"
              : FormatSignificant(r.mapping_error_mm, 3) + " mm") +
       " RMS on the floor (" +
       (!r.mapping_error_source.empty() ? r.mapping_error_source + ", above the held-out lines'"
        : r.few_lines.used              ? "the stated error of a robot's position, above"
        : r.from_landmarks              ? "cross-validated over the landmarks"
                                        : "held-out line pixels") +
       "); " + FormatSignificant(r.mm_per_px, 3) + " mm per px on the robots' plane\n";
  s += r.few_lines.used ? internal::FewLinesHeightText(r.height) : internal::HeightText(r.height);
  long clutter = 0;
  for (const vision::BlobCluster& c : r.colour_clusters) clutter += c.name < 0 ? c.blobs : 0;
  s += internal::ColourFitText(r);
  s += "colour classes (blobs, pixels, separability, nearest):\n  carpet: " +
       std::to_string(r.thresholds.carpet.pixels) + " px\n";
  const std::array<int, 3>& noise = r.thresholds.noise_levels;
  if (noise != std::array<int, 3>{}) {
    s += "  camera noise (the carpet about its median per light cell, box percentiles): Y " +
         std::to_string(noise[0]) + ", U " + std::to_string(noise[1]) + ", V " +
         std::to_string(noise[2]) +
         " levels; a box narrower than its class's median spread by this is widened 1 / (1 + "
         "blobs) of the way\n";
  }
  for (const vision::AutoClassFit& c : r.thresholds.classes) {
    s += "  " + c.name + ": " + std::to_string(c.blobs) + " blobs, " + std::to_string(c.pixels) +
         " px, separability " + FormatSignificant(c.separability, 3) + " from " + c.nearest +
         WidenedText(c.widened_levels) + ThinAlikeText(c.thin_alike) + "\n";
  }
  s += "  clutter (named no class): " + std::to_string(clutter) + " blobs\n";
  const detect::DetectorOptions& t = r.tolerances;
  s += "tolerances: patch_sigma_mm " + FormatSignificant(t.patch_sigma_mm, 3) +
       ", reach_margin_mm " + FormatSignificant(t.reach_margin_mm, 3) + ", area_ratio_min " +
       FormatSignificant(t.area_ratio_min, 3) + " (smallest patch " +
       FormatSignificant(r.smallest_patch_px, 3) + " px), area_ratio_max " +
       FormatSignificant(t.area_ratio_max, 3) + "\n";
  return s + "seconds: " + FormatSignificant(r.seconds, 3) + "\n";
}

}  // namespace patlab::formats

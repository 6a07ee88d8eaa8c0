// The camera's height in patlab setup (camera_setup.h SetupHeight): a view of the floor fixes the
// focal length over the height, the robots' patterns, of a known size at a known height, the rest.
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup_internal.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::formats {
namespace {

// The heights scanned are this factor apart: the robots' plane, at h_r under a camera at h, is
// h / (h - h_r) times the floor's scale; a step changes that by under 3% at h = 6 h_r, well within
// the detector's tolerances (a pattern 13% too large decodes nothing, one a few % off does).
constexpr double kScanStep = 1.15;
// The highest camera scanned (mm): above any field camera measured; a camera higher than that
// sees the robots' plane within 1.2% of the floor's scale (SSL robots, 140 mm), where the robots
// no longer tell heights apart anyway.
constexpr double kHighestCameraMm = 12000.0;

using internal::HeightOf;

// The height's standard error from the fit's: the lines fix f / h, so the height moves with the
// focal length, h se(f) / f. NaN when the fit held f or has no covariance.
double HeightSd(const calib::CalibrationFit& fit) {
  const double se = fit.standard_error[0];
  return se > 0.0 && std::isfinite(se) ? HeightOf(fit.camera) * se / fit.camera.fx_px : NAN;
}

// The camera `scale` times as high with `scale` times the focal length, moved along its optical
// axis away from the floor point the axis meets, the distortion scaled to bend the same pixels:
// for a camera looking straight down the same map of the floor exactly, for a few degrees of tilt
// nearly (the fit with the robots refits the lines).
camera::PinholeCamera Scaled(const camera::PinholeCamera& c, double scale) {
  const Eigen::Vector3d centre = -c.rotation.transpose() * c.translation_mm;
  const Eigen::Vector3d axis = c.rotation.transpose() * Eigen::Vector3d(0.0, 0.0, 1.0);
  const double along = -centre.z() / axis.z();
  const Eigen::Vector3d moved = centre + (1.0 - scale) * along * axis;
  camera::PinholeCamera out = c;
  out.fx_px *= scale;
  out.fy_px *= scale;
  out.k1 *= scale * scale;
  out.k2 *= scale * scale * scale * scale;
  out.translation_mm = -c.rotation * moved;
  return out;
}

// A try of the scan: the setup through one camera and what decodes through it.
struct HeightCandidate {
  SetupResult setup;
  internal::Decoded decoded;
};

}  // namespace

// The calibration fitted again from `start` to the lines and the decoded robots' patches together:
// each robot a pattern observation on the robots' plane, its pose free (calib::FitCamera). The
// patterns' size in mm measures the plane's scale, so the height; where they are, their shapes
// pin the map the lines leave loose far from them (the lens' distortion). InputError when it
// fails.
calib::CalibrationFit internal::FitWithRobots(
    const SetupResult& r, const camera::PinholeCamera& start,
    const std::vector<calib::PatternObservation>& patterns) {
  calib::CalibrationInput in = r.calibration_input;
  in.patterns = patterns;
  in.options.start_camera = start;
  // The lines' fit may have held the focal length (it left the model's range): with the patterns
  // the height, and so the focal length, is measured.
  std::erase(in.options.fixed, calib::FitParameter::kFocal);
  in.options.holdout_folds = 0;
  in.options.covariance = true;
  return calib::FitCamera(in);
}

double internal::FloorSd(const SetupResult& r, int width_px, int height_px) {
  const calib::Field& f = r.field;
  const auto inside = [&f](const Vec2& p) {
    return std::abs(p.x()) <= 0.5 * f.length_mm && std::abs(p.y()) <= 0.5 * f.width_mm;
  };
  return calib::MappingSdOver(r.calibration_fit, width_px, height_px, 0.0, inside, 10);
}

namespace {

// Whether a height's standard error measures it: below the scan's step.
bool Measures(double sd_mm, double height_mm) { return sd_mm < (kScanStep - 1.0) * height_mm; }

}  // namespace

// The fit's standard error of the height from the robots' patches: HeightSd scaled from the fit's
// residual variance (over every pixel, mostly line pixels) to the patches' own, whose centroids
// stray several times further than a line pixel from a line: the height is measured by them.
double internal::RobotsHeightSd(const calib::CalibrationFit& fit, double robot_height_mm) {
  double ratio = 1.0;
  for (const calib::PlaneResiduals& p : fit.planes) {
    if (std::abs(p.height_mm - robot_height_mm) <= camera::kHeightToleranceMm && fit.rms_px > 0.0)
      ratio = std::max(ratio, p.rms_px / fit.rms_px);
  }
  return HeightSd(fit) * ratio;
}

namespace {

// What set the height: the robots when the fit with them was kept, or more robots decode through
// the scan's camera than through the lines'; else the lines if they measure it; else nothing did.
std::string DecidedBy(const SetupHeight& h) {
  if (h.fitted == "kept" || h.robots > h.lines_robots) return "robots";
  return Measures(h.lines_sd_mm, h.lines_height_mm) ? "lines" : "undetermined";
}

// The scan: the lines' camera (first) and, from the height of the shortest focal length the fit
// allows (or twice the robots' height) to that of the longest (or kHighestCameraMm), the camera
// Scaled to each height, each with what decodes through it (the colours kept); h->scan lists them.
std::vector<HeightCandidate> ScanHeights(const std::vector<const camera::Image*>& frames,
                                         const std::vector<std::string>& names,
                                         const detect::DetectorConfig& config,
                                         const SetupOptions& options, const SetupResult& r,
                                         const internal::Decoded& at_lines, SetupHeight* h) {
  const camera::PinholeCamera& lines = r.calibration_fit.camera;
  const double width = frames.front()->width_px;
  const double low = std::max(h->lines_height_mm * calib::kMinFocalWidths * width / lines.fx_px,
                              2.0 * options.robot_height_mm);
  const double high =
      std::min(h->lines_height_mm * calib::kMaxFocalWidths * width / lines.fx_px, kHighestCameraMm);
  std::vector<HeightCandidate> candidates;
  candidates.push_back({r, at_lines});
  for (double height = low; height <= high; height *= kScanStep) {
    if (std::abs(std::log(height / h->lines_height_mm)) < 0.5 * std::log(kScanStep)) continue;
    HeightCandidate c{r, {}};
    c.setup.calibration_fit.camera = Scaled(lines, height / h->lines_height_mm);
    // A lens of the lines' bend at that scale may need a k1 beyond the camera model's range.
    if (!camera::Check(c.setup.calibration_fit.camera).empty()) continue;
    internal::FinishSetup(frames, names, config, options, c.setup, false);
    c.decoded = internal::DecodeThroughFiles(frames, config, c.setup, options.robot_height_mm);
    candidates.push_back(std::move(c));
  }
  for (const HeightCandidate& c : candidates) {
    h->scan.push_back({HeightOf(c.setup.calibration_fit.camera),
                       c.setup.calibration_fit.camera.fx_px, c.decoded.robots,
                       c.decoded.residual_mm2});
  }
  std::sort(h->scan.begin(), h->scan.end(), [](const SetupHeightTry& a, const SetupHeightTry& b) {
    return a.height_mm < b.height_mm;
  });
  return candidates;
}

// The candidate decoding the most robots; a tie keeps the lines' camera (the first) if it is among
// them, else the lowest mean pattern residual.
size_t MostRobots(const std::vector<HeightCandidate>& candidates) {
  size_t best = 0;
  for (size_t i = 1; i < candidates.size(); ++i) {
    const internal::Decoded& a = candidates[i].decoded;
    const internal::Decoded& b = candidates[best].decoded;
    if (a.robots > b.robots ||
        (a.robots == b.robots && best != 0 && a.residual_mm2 < b.residual_mm2)) {
      best = i;
    }
  }
  return best;
}

// The robots' patches of `chosen` and the lines fitted together (FitWithRobots): the calibration
// written into r (its residuals on the robots' plane are the patches', measured) when it measures
// the height more finely than the scan's step, or at all where the lines do not measure it (below),
// more finely than the lines where `chosen` is the lines' own camera (`lines_camera`), and decodes
// as many robots. Whether it was kept; h->fitted says why not.
bool KeepFitWithRobots(const std::vector<const camera::Image*>& frames,
                       const std::vector<std::string>& names, const detect::DetectorConfig& config,
                       const SetupOptions& options, const HeightCandidate& chosen,
                       bool lines_camera, SetupResult& r, SetupHeight* h) {
  SetupResult joint = chosen.setup;
  h->patterns = static_cast<int>(chosen.decoded.patterns.size());
  try {
    joint.calibration_fit =
        internal::FitWithRobots(r, chosen.setup.calibration_fit.camera, chosen.decoded.patterns);
  } catch (const InputError& e) {
    h->fitted = std::string("failed: ") + e.what();
    return false;
  }
  h->fitted_height_mm = HeightOf(joint.calibration_fit.camera);
  h->fitted_sd_mm = internal::RobotsHeightSd(joint.calibration_fit, options.robot_height_mm);
  // A coarse measure beats none. Where the lines do not measure the height either, theirs is
  // wherever their fit stopped, and a low one maps the robots' plane with several times the true
  // parallax: fresh rendered seeds 122 (1.23 m, the focal length's bound, for a true 4.01 m) and
  // 145 (1.67 +- 11.9 m for 4.36 m), 10 and 9 robots decoding alike at every height, 6 and 4 of
  // them put over 100 mm off. The fit with the robots measures what the robots' positions need,
  // the plane's parallax h_r / h: at 5.62 +- 1.21 m and 9.26 +- 3.06 m every robot is within
  // 27 and 45 mm. (Too high a height errs by at most the true parallax, too low by any amount.)
  const bool coarse_kept =
      !Measures(h->lines_sd_mm, h->lines_height_mm) && std::isfinite(h->fitted_sd_mm);
  if (!Measures(h->fitted_sd_mm, h->fitted_height_mm) && !coarse_kept) {
    h->fitted = "not kept: its standard error is over " +
                FormatSignificant(100.0 * (kScanStep - 1.0), 2) + "%, the scan's step";
    return false;
  }
  // Where the robots decode as many through the lines' own camera, the lines' height stands unless
  // the robots measure it more finely.
  if (lines_camera && Measures(h->lines_sd_mm, h->lines_height_mm) &&
      !(h->fitted_sd_mm < h->lines_sd_mm)) {
    h->fitted = "not kept: the lines measure the height more finely";
    return false;
  }
  // The held-out line pixels measure the map on the lines. Where the robots set the height, the
  // error lies away from them too, along the focal length, distortion and height the lines leave
  // loose together, and only the fit's spread over the whole field shows it (rendered seed 3:
  // "below 0.23 mm" on the lines, 9.6 mm over the field): the larger of the two is the
  // error, and the tolerances FinishSetup chooses follow it.
  joint.floor_sd_mm = internal::FloorSd(joint, frames.front()->width_px, frames.front()->height_px);
  if (joint.floor_sd_mm > joint.mapping_error_mm) {
    joint.mapping_error_mm = joint.floor_sd_mm;
    joint.mapping_error_source = "the fit's spread over the field";
  }
  internal::FinishSetup(frames, names, config, options, joint, true);
  const int robots = std::max(joint.robots_by_blobs, joint.robots_by_pixels);
  if (robots < chosen.decoded.robots) {
    h->fitted = "not kept: " + std::to_string(robots) + " robots decode through it, " +
                std::to_string(chosen.decoded.robots) + " through the scan's";
    return false;
  }
  h->fitted = "kept";
  h->robots = robots;
  h->sd_mm = h->fitted_sd_mm;
  r = std::move(joint);
  return true;
}

}  // namespace

// The robots the detector decodes through `thresholds` and the files setup writes: per frame the
// distinct (pattern, team, ID), less one for every further detection of one; with `decoded`, their
// residuals and patch pixels too (internal::Decoded).
int internal::DecodedRobots(const std::vector<const camera::Image*>& frames,
                            const vision::Thresholds& thresholds,
                            const camera::Calibration& calibration,
                            const std::string& settings_text, const detect::DetectorConfig* config,
                            double robot_height_mm, Decoded* decoded) {
  vision::FrameDetectorOptions options;
  vision::ApplyFrameSettings(ParseFrameSettings(settings_text, "settings.toml"), &options);
  vision::FrameDetector detector(
      thresholds, calibration, ParseDetectorSettings(settings_text, "settings.toml", "."), options);
  int score = 0;
  double residual = 0.0;
  int counted = 0;
  for (const camera::Image* frame : frames) {
    std::set<std::array<int, 3>> seen;
    const vision::FrameResult& result = detector.Detect(*frame, "frame");
    for (const detect::Detection& d : result.detections) {
      if (d.id < 0) continue;
      const bool first = seen.insert({d.pattern, d.team_colour, d.id}).second;
      score += first ? 1 : -1;
      if (decoded == nullptr || !first) continue;
      residual += d.residual_mm2, ++counted;
      calib::PatternObservation p;
      p.pattern = config->patterns[static_cast<size_t>(d.pattern)].pattern;
      p.name = "robot " + std::to_string(decoded->patterns.size() + 1);
      p.height_mm = robot_height_mm;
      for (size_t j = 0; j < p.pattern.patches.size(); ++j) {
        const int blob = d.blob[j];
        if (blob < 0) {
          p.pixels.emplace_back(std::nullopt);
          continue;
        }
        const int source = result.detector_blob_source[static_cast<size_t>(blob)];
        p.pixels.emplace_back(result.blob_regions[static_cast<size_t>(source)].centroid_px);
      }
      decoded->patterns.push_back(std::move(p));
    }
  }
  if (decoded != nullptr) {
    decoded->robots = score;
    decoded->residual_mm2 = counted > 0 ? residual / counted : NAN;
  }
  return score;
}

internal::Decoded internal::DecodeThroughFiles(const std::vector<const camera::Image*>& frames,
                                               const detect::DetectorConfig& config,
                                               const SetupResult& r, double robot_height_mm) {
  const auto text = [&](const std::string& name) -> const std::string& {
    for (const auto& [file, t] : r.files)
      if (file == name) return t;
    throw std::logic_error("setup: no " + name + " made");
  };
  Decoded decoded;
  DecodedRobots(frames, r.thresholds.thresholds,
                ParseCalibration(text("calibration.toml"), "calibration.toml"),
                text("settings.toml"), &config, robot_height_mm, &decoded);
  return decoded;
}

void internal::ChooseHeight(const std::vector<const camera::Image*>& frames,
                            const std::vector<std::string>& names,
                            const detect::DetectorConfig& config, const SetupOptions& options,
                            SetupResult& r) {
  SetupHeight h;
  const camera::PinholeCamera lines = r.calibration_fit.camera;
  h.lines_height_mm = h.height_mm = HeightOf(lines);
  h.lines_focal_px = h.focal_px = lines.fx_px;
  h.lines_sd_mm = h.sd_mm = HeightSd(r.calibration_fit);
  const Decoded at_lines = DecodeThroughFiles(frames, config, r, options.robot_height_mm);
  h.lines_robots = h.robots = at_lines.robots;
  const Eigen::Vector3d axis = lines.rotation.transpose() * Eigen::Vector3d(0.0, 0.0, 1.0);
  if (options.camera_height_mm) {
    h.decided_by = "given";
  } else if (options.robot_height_mm <= 0.0 || axis.z() > -0.5) {
    // Patterns on the floor show the floor's scale only; a camera looking more than 60 degrees
    // from straight down is not a view the scan's scaling keeps.
    h.decided_by = "undetermined";
  }
  if (h.decided_by != "lines") {
    r.height = h;
    return;
  }
  const std::vector<HeightCandidate> candidates =
      ScanHeights(frames, names, config, options, r, at_lines, &h);
  const size_t best = MostRobots(candidates);
  const HeightCandidate& chosen = candidates[best];
  if (chosen.decoded.robots <= 0) {
    h.decided_by = "undetermined";
    r.height = h;
    return;
  }
  if (!KeepFitWithRobots(frames, names, config, options, chosen, best == 0, r, &h)) {
    r = chosen.setup;
    h.robots = chosen.decoded.robots;
    h.sd_mm = best == 0 ? h.lines_sd_mm : NAN;
  }
  h.height_mm = HeightOf(r.calibration_fit.camera);
  h.focal_px = r.calibration_fit.camera.fx_px;
  h.decided_by = DecidedBy(h);
  r.height = h;
}

int internal::CreditedRobots(const SetupHeight& h) {
  const bool lines_measure = Measures(h.lines_sd_mm, h.lines_height_mm);
  // A given height fixes the focal length only through the lines' f / h: where they do not
  // measure it, the robots decoded at that focal length are luck (few-lines view 8 with its true
  // height: 8 through a corner's camera 1.4 m off, none through the lines' best).
  if (h.decided_by == "given") return lines_measure ? h.robots : 0;
  const bool robots_measure = Measures(h.fitted_sd_mm, h.fitted_height_mm);
  // The fit with the robots (kept or not) and the lines, each measuring the height, disagree.
  if (lines_measure && robots_measure &&
      std::abs(h.fitted_height_mm - h.lines_height_mm) >
          kHeightAgreement * std::hypot(h.fitted_sd_mm, h.lines_sd_mm)) {
    return 0;
  }
  // A fit kept however coarse (the lines not measuring the height) credits no more than the
  // lines' camera would: its height is no measure a rival's can be told from.
  if (h.fitted == "kept" && robots_measure) return h.robots;
  if (lines_measure) return h.lines_robots;
  // Nothing measures the height: the robots through the lines' camera tell the floor's scale the
  // lines fix only where no height of the scan decodes more (fresh seed 3: 6 robots from 1.5 m to
  // 10.9 m); where one does, the count at the lines' arbitrary height is luck (few-lines view 8:
  // 5 there, 10 from 3.7 m up).
  return h.lines_robots == MostRobotsTried(h) ? h.lines_robots : 0;
}

int internal::MostRobotsTried(const SetupHeight& h) {
  int most = h.lines_robots;
  for (const SetupHeightTry& t : h.scan) most = std::max(most, t.robots);
  return most;
}

std::string internal::Metres(double mm) { return FormatFixed(mm / 1000.0, 2) + " m"; }

std::string internal::HeightText(const SetupHeight& h) {
  using internal::Metres;
  const auto plus_minus = [&](double sd) {
    return std::isfinite(sd) ? " +- " + Metres(sd) : std::string(" (not determined by them)");
  };
  const std::string lines = Metres(h.lines_height_mm) + plus_minus(h.lines_sd_mm) + ", f " +
                            FormatFixed(h.lines_focal_px, 0) + " px";
  const std::string ratio = FormatSignificant(h.lines_focal_px / h.lines_height_mm, 3);
  std::string s = "camera height: ";
  if (h.decided_by == "given") {
    return s + Metres(h.height_mm) + ", f " + FormatFixed(h.focal_px, 0) +
           " px (given: --camera-height; " + std::to_string(h.robots) + " robots decoded)\n";
  }
  int most = 0;
  double from = INFINITY, to = 0.0;
  for (const SetupHeightTry& t : h.scan) most = std::max(most, t.robots);
  for (const SetupHeightTry& t : h.scan) {
    if (t.robots < most) continue;
    from = std::min(from, t.height_mm), to = std::max(to, t.height_mm);
  }
  if (h.decided_by == "undetermined") {
    s += "undetermined: the lines' camera is " + lines + ", but a view of the floor fixes only f " +
         "over the height (" + ratio + " px per mm); ";
    if (h.scan.empty()) {
      s += "the robots, on the floor or seen from the side, do not measure it";
    } else if (most <= 0) {
      s += "no robots decode at any height from " + Metres(h.scan.front().height_mm) + " to " +
           Metres(h.scan.back().height_mm) + " to measure it";
    } else {
      s += std::to_string(most) + " robots decode alike from " + Metres(from) + " to " +
           Metres(to) + " and their patches do not measure it";
    }
    s += "; give --camera-height if the robots' positions matter\n";
  } else {
    s += Metres(h.height_mm) + (std::isfinite(h.sd_mm) ? " +- " + Metres(h.sd_mm) : "") + ", f " +
         FormatFixed(h.focal_px, 0) + " px (the " + h.decided_by + " decide; " +
         std::to_string(h.robots) + " robots decoded through it)\n";
    s += "  the lines alone: " + lines + ", " + std::to_string(h.lines_robots) +
         " robots decoded through it; they fix f over the height, " + ratio + " px per mm\n";
  }
  if (h.patterns > 0) {
    s += "  the lines and " + std::to_string(h.patterns) +
         " decoded robots' patches fitted together: " +
         (h.fitted.starts_with("failed")
              ? h.fitted
              : Metres(h.fitted_height_mm) + plus_minus(h.fitted_sd_mm) + " (" + h.fitted +
                    (h.fitted == "kept" && !Measures(h.fitted_sd_mm, h.fitted_height_mm)
                         ? ": coarse, but the lines do not measure the height at all"
                         : "") +
                    ")") +
         "\n";
  }
  if (!h.scan.empty()) {
    s += "  heights tried, f scaled with them (m: robots decoded):";
    for (const SetupHeightTry& t : h.scan)
      s += " " + FormatFixed(t.height_mm / 1000.0, 2) + ": " + std::to_string(t.robots);
    s += "\n";
  }
  return s;
}

}  // namespace patlab::formats

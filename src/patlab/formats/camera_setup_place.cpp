// Where the field's lines match too few marks to fix a camera, the robots' patterns measure the
// floor's scale and the lines' crossing is placed on the field's (camera_setup.h SetupFewLines).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <regex>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/camera_setup_internal.h"

namespace patlab::formats {
namespace {

constexpr int kFloorScales = 41;
constexpr double kLeastMmPerPx = 0.5, kMostMmPerPx = 20.0;
constexpr double kDefaultBoundaryMm = 1000.0;
constexpr double kSameMapMm = 100.0;
// A different placement explaining at least this share of the kept one's line leaves it undecided
// (placements mapping the frame closer than kSameMapMm are the same). Lower than calib's 0.9 for
// the lines' cameras: a placement explains a corner's few hundred px of line, of which a tenth is
// a few dozen px, as much as robots standing on a line hide (fresh rendered seed 332:
// ssl-2018's midline crossing a defence-area front line kept at 390.5 px against 321.8 px, 0.82,
// for a placement 3.7 m off the true one; every robot decoded there was a false ID).
constexpr double kUndecidedRatio = 0.8;
// Without a camera the colour fit does not know the patches' size in px: the scan is made with its
// given blob bounds and again with bounds for patches down to this radius (px, a patch about 4 px
// across: a 40 mm ID patch at 9.4 mm per px, fresh rendered seed 406, whose six robots gave the
// given bounds (a blob's spread of at least 1 px) one blue, one yellow and one green blob).
constexpr double kSmallPatchPx = 2.0;
// The assignment's gates, the placement's first (the floor camera's tilt is unknown).
constexpr double kGatesPx[] = {12.0, 5.0, 3.0};

// A camera looking straight down at the floor point (0, 0), its focal length the frame's width,
// at the height that gives the floor `mm_per_px`; the principal point at the image centre.
camera::PinholeCamera FloorCamera(double mm_per_px, int width, int height) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = width;
  c.cx_px = 0.5 * (width - 1);
  c.cy_px = 0.5 * (height - 1);
  c.rotation = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  c.translation_mm = -c.rotation * Eigen::Vector3d(0.0, 0.0, mm_per_px * width);
  return c;
}

// The largest reach of a pattern's patches from its centre (mm): how far off a robot's position
// may be and the robot still be found where it is.
double PatternRadiusMm(const detect::DetectorConfig& config) {
  double r = 0.0;
  for (const detect::DetectorPattern& p : config.patterns)
    for (const Patch& patch : p.pattern.patches)
      r = std::max(r, patch.position_mm.norm() + patch.radius_mm);
  return r;
}

// The mean of a decoded robot's seen patch pixels.
std::optional<Vec2> CentroidPx(const calib::PatternObservation& p) {
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (const auto& px : p.pixels)
    if (px) sum += *px, ++n;
  if (n == 0) return std::nullopt;
  return sum / n;
}

// Whether every decoded robot lies on the field or its run-off through `camera`.
bool RobotsOnField(const camera::PinholeCamera& camera, const calib::Field& field,
                   const std::vector<calib::PatternObservation>& patterns, double height_mm) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  const double boundary = field.boundary_mm.value_or(kDefaultBoundaryMm);
  for (const calib::PatternObservation& p : patterns) {
    const std::optional<Vec2> px = CentroidPx(p);
    if (!px) continue;
    const auto q = model.PixelToWorld(*px, height_mm);
    if (!q || std::abs(q->x()) > 0.5 * field.length_mm + boundary ||
        std::abs(q->y()) > 0.5 * field.width_mm + boundary) {
      return false;
    }
  }
  return true;
}

// How far apart (mm) two cameras map a 3 x 3 grid of the frame on the floor, the second also
// turned by 180 deg about the field's centre (the smaller: a point-symmetric field's equivalents).
double FloorDifferenceMm(const camera::PinholeCamera& a, const camera::PinholeCamera& b, int width,
                         int height) {
  const camera::CameraModel ma = camera::CameraModel::Pinhole(a),
                            mb = camera::CameraModel::Pinhole(b);
  double straight = 0.0, turned = 0.0;
  for (double fx : {0.25, 0.5, 0.75})
    for (double fy : {0.25, 0.5, 0.75}) {
      const Vec2 px(fx * width, fy * height);
      const auto qa = ma.PixelToWorld(px, 0.0), qb = mb.PixelToWorld(px, 0.0);
      if (!qa || !qb) return INFINITY;
      straight = std::max(straight, (*qa - *qb).norm());
      turned = std::max(turned, (*qa + *qb).norm());
    }
  return std::min(straight, turned);
}

// The worst decoded robot's position standard error (mm, along its worst axis): the fit's mapping
// covariance at its centroid, scaled from the fit's residuals to the patches' (RobotsHeightSd's
// reasoning). NaN when the fit does not determine it.
double PositionSdMm(const calib::CalibrationFit& fit,
                    const std::vector<calib::PatternObservation>& patterns, double height_mm) {
  double ratio = 1.0;
  for (const calib::PlaneResiduals& p : fit.planes) {
    if (std::abs(p.height_mm - height_mm) <= camera::kHeightToleranceMm && fit.rms_px > 0.0)
      ratio = std::max(ratio, p.rms_px / fit.rms_px);
  }
  double worst = 0.0;
  for (const calib::PatternObservation& p : patterns) {
    const std::optional<Vec2> px = CentroidPx(p);
    if (!px) continue;
    const auto c = calib::MappingCovariance(fit, *px, height_mm);
    if (!c) return NAN;
    const double a = (*c)[0], b = (*c)[1], d = (*c)[3];
    const double largest = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
    worst = std::max(worst, std::sqrt(std::max(0.0, largest)));
  }
  return worst * ratio;
}

// The floor scale decoding the most robots through a camera looking straight down (a tie: the
// lowest mean pattern residual), with what decodes through it; `base` holds the colours.
std::pair<double, internal::Decoded> ScanFloorScales(
    const std::vector<const camera::Image*>& frames, const std::vector<std::string>& names,
    const detect::DetectorConfig& config, const SetupOptions& options, const SetupResult& base) {
  const camera::Image& first = *frames.front();
  double best_scale = 0.0;
  internal::Decoded best;
  for (int i = 0; i < kFloorScales; ++i) {
    const double s =
        kLeastMmPerPx * std::pow(kMostMmPerPx / kLeastMmPerPx, i / (kFloorScales - 1.0));
    SetupResult c = base;
    c.calibration_fit.camera = FloorCamera(s, first.width_px, first.height_px);
    // The calibration file writes the fit's Rodrigues vector: a half turn about x.
    c.calibration_fit.rotation_rodrigues = Eigen::Vector3d(std::numbers::pi, 0.0, 0.0);
    if (internal::HeightOf(c.calibration_fit.camera) <= options.robot_height_mm + 100.0) continue;
    internal::FinishSetup(frames, names, config, options, c, false);
    internal::Decoded d = internal::DecodeThroughFiles(frames, config, c, options.robot_height_mm);
    if (d.robots > best.robots ||
        (d.robots == best.robots && d.robots > 0 && d.residual_mm2 < best.residual_mm2)) {
      best = std::move(d);
      best_scale = s;
    }
  }
  return {best_scale, std::move(best)};
}

// The lines and the robots fitted together from a placement, the line pixels assigned again
// through each fit at narrowing gates. InputError when a fit fails.
calib::CalibrationFit FitPlacement(const calib::Placement& placement,
                                   const std::vector<calib::LinePixel>& pixels,
                                   const calib::Field& field,
                                   const std::vector<calib::PatternObservation>& patterns,
                                   const calib::AutoOptions& auto_options, SetupResult* r) {
  r->calibration_input = placement.input;
  camera::PinholeCamera camera = placement.camera;
  calib::CalibrationFit fit;
  for (double gate : kGatesPx) {
    if (gate != kGatesPx[0]) {
      r->calibration_input = calib::AssignToMarks(
          camera, pixels, field, gate, auto_options.max_fit_pixels, r->calibration_input);
    }
    fit = internal::FitWithRobots(*r, camera, patterns);
    camera = fit.camera;
  }
  return fit;
}

// What the lines matched, without the family's hints.
std::string MatchedText(const std::string& lines_failure) {
  static const std::regex kMatched(
      R"(\d+ line pixels|the line pixels matched \d+ field line\(s\) and \d+ circle\(s\))"
      R"(|the focal length at the fit's lower bound \([^)]*\)[^:]*)"
      R"(|a floor map the robots' patterns do not allow \([^)]*\))");
  std::string text;
  for (auto m = std::sregex_iterator(lines_failure.begin(), lines_failure.end(), kMatched);
       m != std::sregex_iterator(); ++m)
    text += (text.empty() ? "" : "; ") + m->str();
  return text.empty() ? lines_failure : text;
}

// The colours before any camera (from the blobs alone) and the calibration input the fit starts
// from.
SetupResult ColoursWithoutCamera(const std::vector<const camera::Image*>& frames,
                                 const std::vector<std::string>& names,
                                 const detect::DetectorConfig& config, const SetupOptions& options,
                                 const calib::AutoOptions& auto_options) {
  const camera::Image& first = *frames.front();
  SetupResult base;
  base.field = options.fields.front();
  base.calibration_input.source = names.front();
  base.calibration_input.loc = FileLoc{names.front(), 0};
  base.calibration_input.image_width_px = first.width_px;
  base.calibration_input.image_height_px = first.height_px;
  base.calibration_input.options.fixed = auto_options.fixed;
  base.calibration_input.options.huber_px = auto_options.huber_px;
  base.calibration_input.options.camera_height_mm = options.camera_height_mm;
  internal::FitColours(frames, config, options, &base);
  return base;
}

// The best placement (they come best first) that keeps the decoded robots on its field; counts
// those in few->on_field and notes the best one mapping the frame elsewhere in few->runner_up_px.
const calib::Placement* BestOnField(const std::vector<calib::Placement>& placements,
                                    const SetupOptions& options,
                                    const std::vector<calib::PatternObservation>& patterns,
                                    int width_px, int height_px, SetupFewLines* few) {
  const calib::Placement* kept = nullptr;
  for (const calib::Placement& p : placements) {
    const calib::Field& field = options.fields[static_cast<size_t>(p.model)];
    if (p.input.lines.empty() || !RobotsOnField(p.camera, field, patterns, options.robot_height_mm))
      continue;
    ++few->on_field;
    if (kept == nullptr) {
      kept = &p;
    } else if (few->runner_up_px == 0.0 &&
               FloorDifferenceMm(kept->camera, p.camera, width_px, height_px) > kSameMapMm) {
      few->runner_up_px = p.score_px;
    }
  }
  return kept;
}

// The fit of the lines and the robots' patches is refused (InputError after `failed`, with the
// numbers) when its camera leaves the model's range, when it knows a robot's position less
// finely than a pattern's radius, or when another placement mapping the frame elsewhere explains
// nearly as much line.
void RefuseUnfixed(const calib::CalibrationFit& fit, const SetupFewLines& few,
                   const calib::Placement& kept, const calib::Field& field, size_t robots,
                   double scale, bool height_given, const std::string& failed) {
  // A fit that leaves the camera model's range (a lens bent beyond any real one) is no camera.
  if (const auto problems = camera::Check(fit.camera); !problems.empty()) {
    throw InputError(failed + "the fit of the lines and the robots' patches from " + kept.crossing +
                     " of " + field.name + " leaves the camera model's range (" +
                     problems.front().message +
                     "); expected a frame showing more of the field's lines, or give four "
                     "--landmark NAME=X,Y");
  }
  if (!(few.position_sd_mm <= few.limit_mm)) {
    throw InputError(
        failed + std::to_string(robots) + " robots decode at " + FormatSignificant(scale, 3) +
        " mm per px and place the crossing " + kept.crossing + " of " + field.name +
        ", but the fit of the lines and their patches " +
        (std::isfinite(few.position_sd_mm)
             ? "knows a robot's position only to +- " + FormatSignificant(few.position_sd_mm, 3) +
                   " mm (one standard error, the camera's height included), more than a "
                   "pattern's radius (" +
                   FormatSignificant(few.limit_mm, 3) + " mm)"
             : std::string("does not determine a robot's position (no finite standard error)")) +
        (height_given
             ? "; expected a frame showing more of the field's lines, or give four "
               "--landmark NAME=X,Y"
             : "; give --camera-height MM (the camera's measured height above the floor)"));
  }
  // Another corner that keeps the robots on the field and explains nearly as much line (a view
  // of robots near the corner alone, mirrored): neither the lines nor the robots decide.
  if (few.runner_up_px >= kUndecidedRatio * few.score_px) {
    throw InputError(failed + std::to_string(few.on_field) + " of " +
                     std::to_string(few.placements) +
                     " placements of the fields' crossing lines keep the " +
                     std::to_string(robots) + " decoded robots on the field, " + kept.crossing +
                     " of " + field.name + " explaining " + FormatSignificant(few.score_px, 4) +
                     " px of line and another, mapping the frame elsewhere, " +
                     FormatSignificant(few.runner_up_px, 4) +
                     " px; expected a frame showing more of the field's lines, or give four "
                     "--landmark NAME=X,Y (patlab setup --list-landmarks FIELD)");
  }
}

// The camera's height as the few-lines fit of r's `patterns` decoded robots left it: given, or
// the robots'.
void FewLinesHeight(const SetupOptions& options, int patterns, SetupResult* r) {
  SetupHeight& h = r->height;
  h.decided_by = options.camera_height_mm ? "given" : "robots";
  h.height_mm = h.lines_height_mm = internal::HeightOf(r->calibration_fit.camera);
  h.focal_px = h.lines_focal_px = r->calibration_fit.camera.fx_px;
  h.sd_mm = h.fitted_sd_mm = internal::RobotsHeightSd(r->calibration_fit, options.robot_height_mm);
  h.lines_sd_mm = NAN;
  h.fitted_height_mm = h.height_mm;
  h.patterns = patterns;
  h.fitted = "kept";
  h.robots = h.lines_robots = std::max(r->robots_by_blobs, r->robots_by_pixels);
}

}  // namespace

// What decided where the lines alone matched too few marks.
std::string internal::FewLinesText(const SetupFewLines& f) {
  return " (the lines do not fix the camera -- " + f.lines_failure +
         " -- and the robots placed the field)\n  " + std::to_string(f.robots) +
         " robots decode through a camera looking straight down at " +
         FormatSignificant(f.floor_mm_per_px, 3) + " mm per px on the floor" +
         (f.small_patches ? " (the colours fitted for patches down to " +
                                FormatSignificant(kSmallPatchPx, 2) + " px radius)"
                          : std::string()) +
         "; of " + std::to_string(f.placements) + " placements of the models' crossing lines, " +
         std::to_string(f.on_field) + " keep them on the field; kept " + f.crossing + " (" +
         FormatSignificant(f.score_px, 4) + " px of line explained" +
         (f.runner_up_px > 0.0
              ? ", the best different one " + FormatSignificant(f.runner_up_px, 4) + " px"
              : std::string()) +
         ")\n  a robot's position is known to +- " + FormatSignificant(f.position_sd_mm, 3) +
         " mm (one standard error of the fit of the lines and the robots' patches, the camera's "
         "height included; an estimate, not a bound), at most a pattern's radius (" +
         FormatSignificant(f.limit_mm, 3) + " mm) accepted\n";
}

std::string internal::FewLinesHeightText(const SetupHeight& h) {
  using internal::Metres;
  std::string s = "camera height: " + Metres(h.height_mm);
  if (h.decided_by == "given")
    return s + " (given: --camera-height), f " + FormatFixed(h.focal_px, 0) + " px\n";
  return s + (std::isfinite(h.sd_mm) ? " +- " + Metres(h.sd_mm) : std::string()) + ", f " +
         FormatFixed(h.focal_px, 0) + " px (the robots decide: the fit of the lines and " +
         std::to_string(h.patterns) + " decoded robots' patches together; --camera-height MM " +
         "fixes it and the robots' positions better)\n";
}

bool internal::MatchedTooFewMarks(const std::string& failure) {
  return failure.find("the line pixels matched") != std::string::npos;
}

std::string internal::FocalAtItsBound(const calib::FamilyCalibration& family,
                                      const std::vector<calib::Field>& fields,
                                      const std::string& name, int width_px,
                                      const SetupHeight& height) {
  const double bound = calib::kMinFocalWidths * width_px;
  const double f = family.calibration.fit.camera.fx_px;
  if (!family.rivals.empty() || f > bound * (1.0 + 1e-6)) return "";
  if (internal::MostRobotsTried(height) > 0) return "";
  std::string heights;
  if (!height.scan.empty()) {
    heights = " at any height from " + FormatFixed(height.scan.front().height_mm / 1000.0, 2) +
              " to " + internal::Metres(height.scan.back().height_mm);
  }
  return name + ": " + std::to_string(family.calibration.line_pixels) + " line pixels fit " +
         fields[static_cast<size_t>(family.kept)].name + " only with the focal length at the " +
         "fit's lower bound (" + FormatFixed(f, 0) + " px, " +
         FormatSignificant(calib::kMinFocalWidths, 2) + " image widths), and no robot decodes " +
         "through that camera" + heights + ": the lines do not fix the camera";
}

std::string internal::RobotsOnlyAtTheHighest(const calib::FamilyCalibration& family,
                                             const std::vector<calib::Field>& fields,
                                             const std::string& name, const SetupHeight& height) {
  if (!family.rivals.empty() || height.scan.empty() || internal::CreditedRobots(height) != 0)
    return "";
  const SetupHeightTry& top = height.scan.back();
  if (top.robots <= height.lines_robots) return "";
  for (size_t i = 0; i + 1 < height.scan.size(); ++i)
    if (height.scan[i].robots >= top.robots) return "";
  return name + ": " + std::to_string(family.calibration.line_pixels) + " line pixels fit " +
         fields[static_cast<size_t>(family.kept)].name + " only with a floor map the robots' " +
         "patterns do not allow (" + std::to_string(height.lines_robots) +
         " robots decode through the lines' camera, " + internal::Metres(height.lines_height_mm) +
         " up, and the higher the camera the more, " + std::to_string(top.robots) +
         " only through the highest tried, " + internal::Metres(top.height_mm) +
         ", whose robots' plane is nearly at the floor's scale): the lines do not fix the camera";
}

SetupResult internal::SetupFromRobots(const std::vector<const camera::Image*>& frames,
                                      const std::vector<std::string>& names,
                                      const detect::DetectorConfig& config,
                                      const SetupOptions& options,
                                      const std::vector<calib::LinePixel>& pixels,
                                      const std::string& lines_failure) {
  const camera::Image& first = *frames.front();
  SetupFewLines few;
  few.used = true;
  few.lines_failure = MatchedText(lines_failure);
  few.limit_mm = PatternRadiusMm(config);
  calib::AutoOptions auto_options;
  auto_options.camera_height_mm = options.camera_height_mm;
  auto_options.fixed.push_back(calib::FitParameter::kPrincipalPoint);
  SetupResult base = ColoursWithoutCamera(frames, names, config, options, auto_options);
  auto [scale, decoded] = ScanFloorScales(frames, names, config, options, base);
  SetupOptions small = options;
  SetupBlobAreas(kSmallPatchPx, kSmallPatchPx, &small.colours);
  small.colours.max_blob_area_px =
      std::max(small.colours.min_blob_area_px, options.colours.max_blob_area_px);
  SetupResult small_base = ColoursWithoutCamera(frames, names, config, small, auto_options);
  auto [small_scale, small_decoded] = ScanFloorScales(frames, names, config, options, small_base);
  if (small_decoded.robots > decoded.robots) {
    base = std::move(small_base);
    scale = small_scale;
    decoded = std::move(small_decoded);
    few.small_patches = true;
  }
  few.floor_mm_per_px = scale;
  few.robots = decoded.robots;
  const std::string failed = lines_failure + "; the robots do not fix the camera either: ";
  if (decoded.patterns.size() < 2) {
    throw InputError(failed + std::to_string(decoded.patterns.size()) +
                     " robots decode through a camera looking straight down at any floor scale "
                     "from " +
                     FormatSignificant(kLeastMmPerPx, 2) + " to " +
                     FormatSignificant(kMostMmPerPx, 2) +
                     " mm per px; expected a frame showing more of the field's lines, or give "
                     "four --landmark NAME=X,Y (patlab setup --list-landmarks FIELD)");
  }
  const std::vector<calib::Placement> placements = calib::PlaceCrossings(
      pixels, first.width_px, first.height_px, names.front(), options.fields,
      FloorCamera(scale, first.width_px, first.height_px), kGatesPx[0], auto_options);
  few.placements = static_cast<int>(placements.size());
  const calib::Placement* kept =
      BestOnField(placements, options, decoded.patterns, first.width_px, first.height_px, &few);
  if (placements.empty()) {
    throw InputError(failed +
                     "the line pixels show no two crossing lines (each a run of at "
                     "least 8 pixels) to place a crossing of the fields' lines on; "
                     "expected a frame showing more of the field's lines, or give four "
                     "--landmark NAME=X,Y");
  }
  if (kept == nullptr) {
    throw InputError(failed + "of " + std::to_string(few.placements) +
                     " placements of the fields' crossing lines on them, none keeps the " +
                     std::to_string(decoded.patterns.size()) +
                     " decoded robots on the field; expected a frame showing more of the "
                     "field's lines, or give four --landmark NAME=X,Y");
  }
  const calib::Field& field = options.fields[static_cast<size_t>(kept->model)];
  SetupResult r = base;
  r.field = field;
  try {
    r.calibration_fit = FitPlacement(*kept, pixels, field, decoded.patterns, auto_options, &r);
  } catch (const InputError& e) {
    throw InputError(failed + "the fit of the lines and the robots' patches from " +
                     kept->crossing + " of " + field.name + " failed (" + e.what() +
                     "); expected a frame showing more of the field's lines, or give four "
                     "--landmark NAME=X,Y");
  }
  few.crossing = kept->crossing;
  few.score_px = kept->score_px;
  few.position_sd_mm = PositionSdMm(r.calibration_fit, decoded.patterns, options.robot_height_mm);
  RefuseUnfixed(r.calibration_fit, few, *kept, field, decoded.patterns.size(), scale,
                options.camera_height_mm > 0.0, failed);
  r.mapping_error_mm = few.position_sd_mm;
  r.mapping_resolution_mm = 0.0;
  r.tried.push_back(
      {field.name, kept->score_px, r.mapping_error_mm, "", kept->score_px, true, "", ""});
  r.calibration_report = calib::FitReportText(r.calibration_input, r.calibration_fit);
  internal::FinishSetup(frames, names, config, options, r, true);
  FewLinesHeight(options, static_cast<int>(decoded.patterns.size()), &r);
  r.few_lines = few;
  return r;
}

}  // namespace patlab::formats

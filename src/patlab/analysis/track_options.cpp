#include "patlab/analysis/track_options.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "patlab/core/format.h"

namespace patlab::analysis {

namespace {

// Radius around the subject's origin that the subject covers (mm).
double PatternExtentMm(const Pattern& pattern) {
  double extent = 0.0;
  for (const Patch& p : pattern.patches) {
    extent = std::max(extent, p.position_mm.norm() + p.BoundingRadius());
  }
  return extent;
}

std::vector<double> SubjectExtentsMm(const TrackOptions& o) {
  std::vector<double> extents;
  extents.reserve(o.diameters_mm.size() + 1);
  for (double d : o.diameters_mm) extents.push_back(0.5 * d);
  if (HasPattern(o)) extents.push_back(PatternExtentMm(o.pattern));
  return extents;
}

void CheckSubjects(const TrackOptions& o, OptionsChecker* check) {
  check->IntegerInRange("runs", o.runs, 1, 1000);
  if (o.diameters_mm.empty()) {
    check->Fail("diameters_mm", "diameters_mm is empty; expected at least one diameter (mm)");
  }
  for (size_t i = 0; i < o.diameters_mm.size(); ++i) {
    const double d = o.diameters_mm[i];
    if (!(std::isfinite(d) && d > 0.0)) {
      check->Fail("diameters_mm",
                  "diameters_mm has " + FormatNumber(d) + "; expected diameters > 0 (mm)");
    }
    if (std::find(o.diameters_mm.begin(), o.diameters_mm.begin() + i, d) !=
        o.diameters_mm.begin() + i) {
      check->Fail("diameters_mm",
                  "diameters_mm lists " + FormatNumber(d) + " twice; expected distinct diameters");
    }
  }
}

void CheckPlatform(const TrackOptions& o, OptionsChecker* check) {
  const int min_samples = 2 * o.trim_samples + 3;
  check
      ->Require("samples_per_run", o.samples_per_run,
                o.samples_per_run >= min_samples && o.samples_per_run <= 1'000'000,
                "an integer in [" + std::to_string(min_samples) +
                    ", 1000000] (2 trim_samples + 3 or more)")
      .Positive("rate_hz", o.rate_hz, "frames per second")
      .NonNegative("speed_mm_per_s", o.speed_mm_per_s, "mm/s")
      .InRange("heading_max_deg", o.heading_max_deg, 0.0, 45.0, "degrees")
      .NonNegative("lateral_range_mm", o.lateral_range_mm, "mm")
      .NonNegative("start_jitter_mm", o.start_jitter_mm, "mm")
      .Positive("spacing_mm", o.spacing_mm, "mm")
      .Require("plane_height_mm", o.plane_height_mm,
               o.plane_height_mm < o.camera.height_mm && o.plane_height_mm > -1e6,
               "a number below camera.height_mm (" + FormatNumber(o.camera.height_mm) + ")");
}

void CheckCamera(const TrackCamera& c, OptionsChecker* check) {
  check->Positive("height_mm", c.height_mm, "mm");
  for (int v : {c.image_width_px, c.image_height_px}) {
    if (v < 16 || v > 20000) {
      check->Fail("image_size_px", check->Name("image_size_px") + " has " + std::to_string(v) +
                                       "; expected two integers in [16, 20000] (width, height)");
      break;
    }
  }
  check->Positive("focal_length_px", c.focal_length_px, "px");
}

void CheckRender(const TrackOptions& o, OptionsChecker* check) {
  check->IntegerInRange("background_level", o.background_level, 0, 255)
      .Require("patch_level", o.patch_level,
               o.patch_level > o.background_level && o.patch_level <= 255,
               "an integer in [" + std::to_string(o.background_level + 1) +
                   ", 255] (white patches on a darker floor, above background_level)")
      .Require("threshold_level", o.threshold_level,
               o.threshold_level > o.background_level && o.threshold_level <= o.patch_level,
               "an integer in [" + std::to_string(o.background_level + 1) + ", " +
                   std::to_string(o.patch_level) +
                   "] (above background_level, at most patch_level)")
      .IntegerInRange("supersampling", o.supersampling, 1, 32);
}

std::vector<OptionsProblem> CheckFields(const TrackOptions& o) {
  std::vector<OptionsProblem> problems;
  auto take = [&problems](OptionsChecker* check) {
    for (OptionsProblem& p : check->Take()) problems.push_back(std::move(p));
  };
  OptionsChecker top, platform("platform"), camera("camera"), render("render"), noise("noise"),
      analysis("analysis");
  CheckSubjects(o, &top);
  CheckPlatform(o, &platform);
  CheckCamera(o.camera, &camera);
  CheckRender(o, &render);
  noise.NonNegative("pixel_sigma", o.pixel_sigma, "grey levels")
      .NonNegative("jitter_sigma_px", o.jitter_sigma_px, "px");
  analysis
      .Require("smoothing_sigma_samples", o.smoothing_sigma_samples,
               o.smoothing_sigma_samples > 0.0 && o.smoothing_sigma_samples <= 10000,
               "a number in (0, 10000] (samples)")
      .Require("trim_samples", o.trim_samples, o.trim_samples >= 0, "an integer >= 0");
  for (OptionsChecker* c : {&top, &platform, &camera, &render, &noise, &analysis}) take(c);
  return problems;
}

// Geometry of valid fields: neighbours must not touch, and every subject must stay inside the
// image for the whole run, with the render window margin and 6 sigma of camera jitter.
std::vector<OptionsProblem> CheckGeometry(const TrackOptions& o) {
  OptionsChecker check("platform");
  const double mm_per_px = MmPerPixel(o);
  const std::vector<double> extents = SubjectExtentsMm(o);
  for (size_t k = 1; k < extents.size(); ++k) {
    const double needed = extents[k - 1] + extents[k] + 2 * mm_per_px;
    if (!(o.spacing_mm > needed)) {
      check.Require("spacing_mm", o.spacing_mm, false,
                    "more than " + FormatSignificant(needed, 4) +
                        " mm so that neighbouring subjects do not touch");
      return check.Take();
    }
  }
  const double h = o.heading_max_deg * std::numbers::pi / 180.0;
  const double max_offset = std::abs(SubjectOffsetMm(o, 0));
  const double max_extent = *std::max_element(extents.begin(), extents.end());
  const double margin_mm = (kWindowMarginPx + 2 + 6 * o.jitter_sigma_px) * mm_per_px + max_extent;
  const double reach_x =
      0.5 * TravelMm(o) + o.start_jitter_mm + max_offset * std::sin(h) + margin_mm;
  const double reach_y =
      0.5 * o.lateral_range_mm + 0.5 * TravelMm(o) * std::sin(h) + max_offset + margin_mm;
  const double view_x = 0.5 * (o.camera.image_width_px - 1) * mm_per_px;
  const double view_y = 0.5 * (o.camera.image_height_px - 1) * mm_per_px;
  if (reach_x > view_x || reach_y > view_y) {
    check.Fail("samples_per_run",
               "the track does not fit in the image: subjects reach +-" +
                   FormatSignificant(reach_x, 5) + " x +-" + FormatSignificant(reach_y, 5) +
                   " mm from the image centre but the view is +-" + FormatSignificant(view_x, 5) +
                   " x +-" + FormatSignificant(view_y, 5) +
                   " mm; expected a shorter track (samples_per_run, speed_mm_per_s), a smaller "
                   "lateral_range_mm, spacing_mm or heading_max_deg, or a larger image");
  }
  return check.Take();
}

}  // namespace

std::vector<OptionsProblem> Check(const TrackOptions& options) {
  std::vector<OptionsProblem> problems = CheckFields(options);
  if (!problems.empty()) return problems;
  return CheckGeometry(options);
}

void Validate(const TrackOptions& options) { ThrowFirstProblem(Check(options)); }

double MmPerPixel(const TrackOptions& o) {
  return (o.camera.height_mm - o.plane_height_mm) / o.camera.focal_length_px;
}

bool HasPattern(const TrackOptions& o) { return !o.pattern_file.empty(); }

int NumSubjects(const TrackOptions& o) {
  return static_cast<int>(o.diameters_mm.size()) + (HasPattern(o) ? 1 : 0);
}

std::vector<std::string> SubjectNames(const TrackOptions& o) {
  std::vector<std::string> names;
  for (double d : o.diameters_mm) names.push_back(FormatNumber(d) + "mm");
  if (HasPattern(o)) names.push_back(o.pattern.name);
  return names;
}

double TravelMm(const TrackOptions& o) {
  return o.speed_mm_per_s * (o.samples_per_run - 1) / o.rate_hz;
}

double SubjectOffsetMm(const TrackOptions& o, int subject) {
  return (subject - 0.5 * (NumSubjects(o) - 1)) * o.spacing_mm;
}

}  // namespace patlab::analysis

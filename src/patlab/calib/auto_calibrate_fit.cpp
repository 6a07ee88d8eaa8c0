// The automatic field calibration's fit (auto_calibrate.h steps 3-5): line pixels assigned to
// the painted marks, FitCamera and the held-out error (the report: auto_calibrate_report.cpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "patlab/calib/auto_calibrate_internal.h"
#include "patlab/calib/calibrate_internal.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::calib {
namespace {

using internal::PinholeOf;
using internal::Turned;

constexpr double kMaxAngle =
    0.42;                      // |sin| between a pixel's direction and its mark's, on the floor
constexpr int kMinPixels = 8;  // an observation's pixels at least
// An arc's pixels bend at least this far (RMS px from their best straight line) to measure a
// curvature; line pixels lie within about 0.5 px of their line.
constexpr double kMinBendPx = 1.0;
constexpr int kRun = 8;              // the held-out folds' run length along a mark
constexpr double kLastGatePx = 3.0;  // the assignment's last (narrowest) gate
// A fitted camera explains at most this many px of line per line pixel found (header of FitView).
constexpr double kMaxExplainedPerPixel = 1.5;
// The different cameras fitted from the search's views at most (a further view is fitted while it
// scores at least 80% of the first; FitSearched).
constexpr size_t kFittedViews = 2;

struct Assigned {
  CalibrationInput input;
  int count = 0;
  std::vector<std::vector<double>> line_order, circle_order;  // position along the mark
};

// Each pixel to the nearest painted mark (on the floor) within gate_px and of its direction.
Assigned Assign(const camera::PinholeCamera& camera, const std::vector<LinePixel>& pixels,
                const Field& field, const FieldMarks& marks, double gate_px, int max_pixels,
                const CalibrationInput& base) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  const size_t n_marks = marks.segments.size() + marks.arcs.size();
  std::vector<std::vector<std::pair<double, Vec2>>> groups(n_marks);
  for (const LinePixel& p : pixels) {
    const auto q = model.PixelToWorld(p.pixel, 0.0);
    const auto q2 = model.PixelToWorld(p.pixel + 2.0 * p.direction, 0.0);
    if (!q || !q2) continue;
    const double mm_per_px = std::sqrt(model.AreaScale(p.pixel, 0.0));
    if (!(mm_per_px > 0.0)) continue;
    const Vec2 dir = (*q2 - *q).normalized();
    double best = gate_px * mm_per_px;
    int best_mark = -1;
    double position = 0.0;
    for (size_t m = 0; m < n_marks; ++m) {
      double d, along;
      Vec2 tangent;
      if (m < marks.segments.size()) {
        const MarkSegment& s = marks.segments[m];
        d = DistanceToMark(s, *q);
        tangent = (s.to_mm - s.from_mm).normalized();
        along = (*q - s.from_mm).dot(tangent);
      } else {
        const MarkArc& a = marks.arcs[m - marks.segments.size()];
        d = DistanceToMark(a, *q);
        const Vec2 r = *q - a.centre_mm;
        tangent = Vec2(-r.y(), r.x()).normalized();
        along = std::atan2(r.y(), r.x()) - a.start_rad;
        along -= 2 * std::numbers::pi * std::floor(along / (2 * std::numbers::pi));
      }
      if (d < best && std::abs(tangent.x() * dir.y() - tangent.y() * dir.x()) < kMaxAngle) {
        best = d;
        best_mark = static_cast<int>(m);
        position = along;
      }
    }
    if (best_mark >= 0) groups[static_cast<size_t>(best_mark)].emplace_back(position, p.pixel);
  }
  size_t total = 0;
  for (const auto& g : groups) total += g.size();
  Assigned out;
  out.input = base;
  const double keep = total > static_cast<size_t>(max_pixels)
                          ? static_cast<double>(max_pixels) / static_cast<double>(total)
                          : 1.0;
  for (size_t m = 0; m < n_marks; ++m) {
    auto& g = groups[m];
    if (g.size() < static_cast<size_t>(kMinPixels)) continue;
    std::sort(g.begin(), g.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const size_t n = std::max<size_t>(kMinPixels, static_cast<size_t>(g.size() * keep));
    std::vector<Vec2> px;
    std::vector<double> order;
    for (size_t i = 0; i < n; ++i) {
      const auto& e = g[i * g.size() / n];
      px.push_back(e.second);
      order.push_back(e.first);
    }
    out.count += static_cast<int>(g.size());
    if (m < marks.segments.size()) {
      const FieldLine& l = field.lines[static_cast<size_t>(marks.segments[m].line)];
      out.input.lines.push_back({l.name, l.from_mm, l.to_mm, 0.0, px, base.loc});
      out.line_order.push_back(order);
    } else {
      const FieldCircle& c =
          field.circles[static_cast<size_t>(marks.arcs[m - marks.segments.size()].circle)];
      out.input.circles.push_back({c.name, c.centre_mm, c.radius_mm, 0.0, px, base.loc});
      out.circle_order.push_back(order);
    }
  }
  return out;
}

// Whether the observations fix a camera: straight lines in two directions, or a circle and a
// line, with enough pixels. An arc whose pixels do not bend in the image (within kMinBendPx of a
// straight line) measures no curvature: it counts as a line (a single straight field line
// otherwise fits a small camera matching it to a short piece of arc and a line).
std::string WhatIsMissing(const CalibrationInput& in) {
  std::vector<Vec2> dirs;
  for (const LineObservation& l : in.lines) dirs.push_back((l.to_mm - l.from_mm).normalized());
  size_t bending = 0;
  for (const CircleObservation& c : in.circles)
    bending += internal::BendPx(c.pixels) >= kMinBendPx ? 1 : 0;
  bool crossing = false;
  for (size_t i = 0; i < dirs.size(); ++i)
    for (size_t j = i + 1; j < dirs.size(); ++j)
      crossing = crossing || std::abs(dirs[i].x() * dirs[j].y() - dirs[i].y() * dirs[j].x()) > 0.5;
  if (crossing && in.lines.size() + in.circles.size() >= 3) return "";
  if (bending > 0 && in.lines.size() + in.circles.size() >= 2) return "";
  return "the line pixels matched " + std::to_string(in.lines.size()) + " field line(s) and " +
         std::to_string(in.circles.size()) + " circle(s)" +
         (bending < in.circles.size() ? " (" + std::to_string(in.circles.size() - bending) +
                                            " of them straight in the image: their pixels within " +
                                            FormatSignificant(kMinBendPx, 2) + " px of a line)"
                                      : std::string());
}

// The two folds of `all`: runs of kRun pixels along each observation alternate.
CalibrationInput Fold(const CalibrationInput& all, int fold) {
  CalibrationInput in = all;
  auto keep = [&](std::vector<Vec2>& px) {
    std::vector<Vec2> out;
    for (size_t i = 0; i < px.size(); ++i)
      if (static_cast<int>(i / kRun) % 2 == fold) out.push_back(px[i]);
    px = out;
  };
  for (auto& l : in.lines) keep(l.pixels);
  for (auto& c : in.circles) keep(c.pixels);
  std::erase_if(in.lines, [](const LineObservation& l) { return l.pixels.size() < 3; });
  std::erase_if(in.circles, [](const CircleObservation& c) { return c.pixels.size() < 3; });
  return in;
}

// FloorDistanceMm with a sign: left of the line's direction, or outside the circle, positive.
double SignedFloorDistanceMm(const camera::PinholeCamera& camera, const Vec2& pixel,
                             const LineObservation* line, const CircleObservation* circle) {
  const auto q = camera::CameraModel::Pinhole(camera).PixelToWorld(pixel, 0.0);
  if (!q) return std::numeric_limits<double>::quiet_NaN();
  if (line != nullptr) {
    const Vec2 d = (line->to_mm - line->from_mm).normalized();
    const Vec2 r = *q - line->from_mm;
    return d.x() * r.y() - d.y() * r.x();
  }
  return (*q - circle->centre_mm).norm() - circle->radius_mm;
}

}  // namespace

double FloorDistanceMm(const camera::PinholeCamera& camera, const Vec2& pixel,
                       const LineObservation* line, const CircleObservation* circle) {
  return std::abs(SignedFloorDistanceMm(camera, pixel, line, circle));
}

namespace {

void CheckAutoInput(const std::vector<LinePixel>& pixels, int width_px, int height_px,
                    const std::string& source, const AutoOptions& options) {
  if (width_px < 16 || height_px < 16)
    throw InputError(source + ": a " + std::to_string(width_px) + " x " +
                     std::to_string(height_px) + " frame; expected at least 16 x 16 px");
  if (!(options.huber_px > 0.0) || options.max_fit_pixels < 50 || !(options.settle_px >= 0.0))
    throw InputError(
        "auto calibration: huber_px must be > 0, max_fit_pixels >= 50 and settle_px >= 0");
  constexpr size_t kMinLinePixels = 100;
  if (pixels.size() < kMinLinePixels) {
    throw InputError(source + ": found " + std::to_string(pixels.size()) +
                     " line pixels; expected at least " + std::to_string(kMinLinePixels) +
                     " (white field lines on the carpet; check --line-width and the frame)");
  }
}

// A view's camera through steps 3-4 (assignment and fit at shrinking gates).
struct Candidate {
  Assigned assigned;
  CalibrationFit fit;
  double score = -INFINITY;
  bool turned = false;
  std::string failure;
};

struct FitContext {
  const std::vector<LinePixel>* pixels;
  const Field* field;
  const FieldMarks* marks;
  const internal::LineDistance* dt;
  const AutoOptions* options;
  int width_px, height_px;
  bool point_symmetric;
};

// The fit at one gate; the focal length held when the free fit leaves the camera model's range.
// Only the last gate's fit computes the covariance (the only one whose numbers are kept).
void FitAtGate(const FitContext& x, double gate, CalibrationInput& base, camera::PinholeCamera& cam,
               Candidate& c, std::vector<std::string>* notes) {
  c.assigned = Assign(cam, *x.pixels, *x.field, *x.marks, gate, x.options->max_fit_pixels, base);
  const std::string missing = WhatIsMissing(c.assigned.input);
  if (!missing.empty()) throw InputError(missing);
  c.assigned.input.options.start_camera = cam;
  c.assigned.input.options.covariance = gate <= kLastGatePx;
  const bool focal_free = std::find(base.options.fixed.begin(), base.options.fixed.end(),
                                    FitParameter::kFocal) == base.options.fixed.end();
  bool hold = false;
  try {
    c.fit = FitCamera(c.assigned.input);
    hold = !camera::Check(c.fit.camera).empty();
  } catch (const InputError&) {
    if (!focal_free) throw;  // refused with the focal length held: nothing left to hold
    hold = true;             // refused as unphysical (FitCamera's UnphysicalFitReason)
  }
  if (hold) {
    // The floor alone hardly separates the focal length from the height, and the fit wandered
    // along that valley out of the camera model's range (or out of physical bounds): the focal
    // length is held at the start's instead (the floor's mapping is the same along the valley).
    base.options.fixed.push_back(FitParameter::kFocal);
    c.assigned.input.options.fixed = base.options.fixed;
    c.fit = FitCamera(c.assigned.input);
    notes->push_back("the focal length was held at " + FormatSignificant(cam.fx_px, 4) +
                     " px: fitted freely it left the camera model's range");
  }
  cam = c.fit.camera;
}

Candidate FitView(const FitContext& x, const camera::PinholeCamera& start, CalibrationInput& base,
                  std::vector<std::string>* notes) {
  Candidate c;
  camera::PinholeCamera cam = start;
  if (x.point_symmetric) {
    const auto look = camera::CameraModel::Pinhole(cam).PixelToWorld(
        Vec2(0.5 * (x.width_px - 1), 0.5 * (x.height_px - 1)), 0.0);
    if (look && (look->x() < -1.0 || (std::abs(look->x()) <= 1.0 && look->y() < 0.0))) {
      cam = Turned(cam);
      c.turned = true;
    }
  }
  try {
    for (double gate : {12.0, 5.0, kLastGatePx}) FitAtGate(x, gate, base, cam, c, notes);
    c.score = internal::CameraScore(cam, *x.marks, *x.dt);
    // The score is line length in px, about one line pixel per px of line: a camera that
    // explains far more than was found piles the field's marks onto the lines (a far, degenerate
    // view), however well its few observations fit.
    const double found = static_cast<double>(x.pixels->size());
    if (c.score > kMaxExplainedPerPixel * found) {
      c.failure = "its camera explains " + FormatSignificant(c.score, 4) + " px of line from " +
                  std::to_string(x.pixels->size()) +
                  " line pixels (the field's marks piled onto the lines)";
      c.score = -INFINITY;
    } else if (const auto sky = internal::AboveHorizon(cam, x.width_px, x.height_px)) {
      const Eigen::Vector3d centre = -cam.rotation.transpose() * cam.translation_mm;
      c.failure = "its camera, " + FormatFixed(centre.z(), 0) + " mm over the floor and " +
                  FormatFixed(internal::TiltDeg(cam), 1) +
                  " deg from straight down, sees above the horizon at (" +
                  FormatFixed(sky->x(), 0) + ", " + FormatFixed(sky->y(), 0) +
                  ") px (a camera over the field sees the floor in every pixel)";
      c.score = -INFINITY;
    }
  } catch (const InputError& e) {
    c.failure = e.what();
  }
  return c;
}

// Step 5's sums: the held-out pixels' floor distances in runs along their marks.
struct HeldOutSums {
  double sum = 0.0, worst = 0.0, run_sq = 0.0, within = 0.0, inverse_n = 0.0;
  int count = 0, runs = 0, within_dof = 0;

  void AddRun(const std::vector<double>& d) {
    double mean = 0.0;
    for (double x : d) {
      sum += x * x, worst = std::max(worst, std::abs(x)), ++count;
      mean += x;
    }
    if (d.size() < 4) return;
    mean /= static_cast<double>(d.size());
    for (double x : d) within += (x - mean) * (x - mean);
    within_dof += static_cast<int>(d.size()) - 1;
    run_sq += mean * mean, inverse_n += 1.0 / static_cast<double>(d.size()), ++runs;
  }
  void AddMark(const camera::PinholeCamera& camera, const std::vector<Vec2>& pixels,
               const LineObservation* l, const CircleObservation* c) {
    std::vector<double> run;
    for (size_t i = 0; i < pixels.size(); ++i) {
      if (i % kRun == 0 && !run.empty()) AddRun(run), run.clear();
      const double d = SignedFloorDistanceMm(camera, pixels[i], l, c);
      if (std::isfinite(d)) run.push_back(d);
    }
    if (!run.empty()) AddRun(run);
  }
};

// A fitted candidate's camera and observations into `out`; the held-out error is measured
// later, for the cameras kept only (MeasureHeldOut).
void Keep(const Candidate& c, AutoCalibration& out) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  out.score_px = c.score;
  out.turned = c.turned;
  out.input = c.assigned.input;
  out.fit = c.fit;
  out.assigned_pixels = c.assigned.count;
  out.held_out_rms_mm = out.held_out_worst_mm = kNaN;
  out.held_out_mapping_mm = out.held_out_noise_mm = out.held_out_resolution_mm = kNaN;
  out.held_out_count = 0;
}

}  // namespace

void internal::MeasureHeldOut(AutoCalibration& out) {
  HeldOutSums h;
  for (int fold = 0; fold < 2; ++fold) {
    CalibrationInput train = Fold(out.input, fold);
    const CalibrationInput test = Fold(out.input, 1 - fold);
    train.options.start_camera = out.fit.camera;
    train.options.covariance = false;  // only the fold's camera is used
    if (!WhatIsMissing(train).empty()) continue;
    CalibrationFit f;
    try {
      f = FitCamera(train);
    } catch (const InputError& e) {
      // Half the pixels may not hold the camera inside the model's range: that fold says nothing.
      out.notes.push_back("held-out fold " + std::to_string(fold + 1) +
                          " left out: its camera was refused (" + e.what() + ")");
      continue;
    }
    for (const LineObservation& l : test.lines) h.AddMark(f.camera, l.pixels, &l, nullptr);
    for (const CircleObservation& c : test.circles) h.AddMark(f.camera, c.pixels, nullptr, &c);
  }
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  out.held_out_count = h.count;
  out.held_out_rms_mm = h.count > 0 ? std::sqrt(h.sum / h.count) : kNaN;
  out.held_out_worst_mm = h.worst;
  const double noise_var = h.within_dof > 0 ? h.within / h.within_dof : 0.0;
  out.held_out_noise_mm = std::sqrt(noise_var);
  out.held_out_resolution_mm =
      h.runs > 0 ? 2.0 * std::sqrt(noise_var * h.inverse_n / h.runs) : kNaN;
  out.held_out_mapping_mm =
      h.runs > 0 ? std::sqrt(std::max(0.0, h.run_sq / h.runs - noise_var * h.inverse_n / h.runs))
                 : kNaN;
}

internal::Searched internal::SearchField(const std::vector<LinePixel>& pixels, int width_px,
                                         int height_px, const std::string& source,
                                         const Field& field, const AutoOptions& options) {
  CheckAutoInput(pixels, width_px, height_px, source, options);
  Searched s;
  s.marks = PaintedMarks(field);
  s.point_symmetric = PointSymmetric(field);
  try {
    s.views = SearchViews(pixels, width_px, height_px, s.marks, s.point_symmetric, &s.hypotheses);
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
  return s;
}

AutoCalibration AutoCalibrate(const std::vector<LinePixel>& pixels, int width_px, int height_px,
                              const std::string& source, const Field& field,
                              const AutoOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const internal::Searched searched =
      internal::SearchField(pixels, width_px, height_px, source, field, options);
  AutoCalibration out =
      internal::FitSearched(searched, pixels, width_px, height_px, source, field, options);
  internal::MeasureHeldOut(out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

AutoCalibration internal::FitSearched(const Searched& searched,
                                      const std::vector<LinePixel>& pixels, int width_px,
                                      int height_px, const std::string& source, const Field& field,
                                      const AutoOptions& options,
                                      std::vector<AutoCalibration>* undecided) {
  const auto t0 = std::chrono::steady_clock::now();
  AutoCalibration out;
  out.line_pixels = static_cast<int>(pixels.size());
  out.point_symmetric = searched.point_symmetric;
  out.hypotheses = searched.hypotheses;
  const FieldMarks& marks = searched.marks;
  const std::vector<internal::ScoredView>& views = searched.views;
  const internal::LineDistance dt(pixels, width_px, height_px);
  // The base input: the frame and the fit's options (step 5 measures the held-out error).
  CalibrationInput base = internal::BaseInput(source, width_px, height_px, options);
  // Steps 3-4 from the best views; the best final camera wins.
  const FitContext context{&pixels,  &field,   &marks,    &dt,
                           &options, width_px, height_px, out.point_symmetric};
  // A view whose lines match too few marks to fix a camera (a T of two lines fits many places
  // of a field) fails at once and takes no place; a view that starts where a camera fitted
  // before maps the frame (SameMap) is not fitted, and one whose fit lands there keeps only the
  // better of the two: the next view scoring 80% of the best is fitted instead, until
  // kFittedViews different cameras have fitted. Fresh rendered seed 263: the three best views of
  // a centre view converged to one quarter-turned camera, which took both places, and the true
  // camera, the fourth view, was never fitted.
  std::vector<Candidate> candidates;
  const auto fitted_before = [&](const camera::PinholeCamera& camera) {
    return std::find_if(candidates.begin(), candidates.end(), [&](const Candidate& o) {
      double differ = 0.0;
      return std::isfinite(o.score) &&
             SameMap(o.fit.camera, camera, out.point_symmetric, width_px, height_px, &differ);
    });
  };
  size_t fitted = 0;
  for (size_t v = 0; v < views.size() && fitted < kFittedViews; ++v) {
    if (v > 0 && views[v].score < 0.8 * views[0].score) break;  // clearly worse: not fitted
    if (fitted_before(views[v].camera) != candidates.end()) continue;
    Candidate c = FitView(context, views[v].camera, base, &out.notes);
    if (!std::isfinite(c.score)) {
      candidates.push_back(std::move(c));
      continue;
    }
    const auto repeat = fitted_before(c.fit.camera);
    if (repeat == candidates.end()) {
      candidates.push_back(std::move(c));
      ++fitted;
    } else if (c.score > repeat->score) {
      *repeat = std::move(c);
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  const Candidate& best = candidates.front();
  if (!std::isfinite(best.score)) {
    throw InputError(source + ": " + std::to_string(pixels.size()) +
                     " line pixels, but no camera fits them to the field " + field.name + " (" +
                     best.failure + "); expected a frame whose lines cross");
  }
  const bool second = candidates.size() > 1 && std::isfinite(candidates[1].score);
  out.runner_up_px = second ? candidates[1].score : 0.0;
  double differ = 0.0;
  if (second &&
      Undecided(best.fit.camera, best.score, candidates[1].fit.camera, candidates[1].score,
                out.point_symmetric, width_px, height_px, &differ) &&
      !OwnLinesDecide(ExclusiveLinePixels(best.fit.camera, marks, candidates[1].fit.camera, marks,
                                          pixels, width_px, height_px))) {
    if (undecided == nullptr) {
      throw InputError(source + ": the line pixels do not decide the camera: two cameras " +
                       FormatSignificant(differ, 3) + " mm apart on the floor explain " +
                       FormatSignificant(best.score, 4) + " and " +
                       FormatSignificant(candidates[1].score, 4) +
                       " px of line; expected a frame showing more of the field's lines");
    }
    AutoCalibration other = out;
    Keep(candidates[1], other);
    undecided->push_back(std::move(other));
  }
  Keep(best, out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

CalibrationInput AssignToMarks(const camera::PinholeCamera& camera,
                               const std::vector<LinePixel>& pixels, const Field& field,
                               double gate_px, int max_pixels, const CalibrationInput& base) {
  CalibrationInput in = base;
  in.lines.clear(), in.circles.clear();
  return Assign(camera, pixels, field, PaintedMarks(field), gate_px, max_pixels, in).input;
}

}  // namespace patlab::calib

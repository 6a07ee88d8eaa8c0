// The cross-validated mapping error of calibrate.h (CalibrationFit::heldout_rms_mm): k-fold
// cross-validation (Hastie, Tibshirani & Friedman, "The Elements of Statistical Learning",
// section 7.10). The in-sample residual in mm is what the fit minimised, and with one free
// nuisance unknown per line or circle pixel it is several times smaller than the error of points
// the fit never saw; a held-out pixel's back-projection measures that error directly.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/calibrate_internal.h"
#include "patlab/core/format.h"

namespace patlab::calib::internal {

namespace {

// A held-out pixel: where it is, its plane, and how far a floor point is from its target.
struct HeldPixel {
  Vec2 pixel = Vec2::Zero();
  double height_mm = 0.0;
  int kind = 0;  // 0 point, 1 line, 2 circle
  size_t index = 0;
};

double DistanceToTarget(const CalibrationInput& in, const HeldPixel& h, const Vec2& q) {
  if (h.kind == 0) return (q - in.points[h.index].world_mm).norm();
  if (h.kind == 1) {
    const LineObservation& l = in.lines[h.index];
    const Vec2 u = (l.to_mm - l.from_mm).normalized();
    const Vec2 d = q - l.from_mm;
    return std::abs(d.x() * u.y() - d.y() * u.x());
  }
  const CircleObservation& c = in.circles[h.index];
  return std::abs((q - c.centre_mm).norm() - c.radius_mm);
}

// The pixels of line or circle observations (`kind` 1 or 2) with their nuisance parameters (a
// line's position, a circle's angle): those `is_held` picks into `held`, the others into `train`
// and `train_params`; an observation left without pixels is dropped. Returns the pixels kept.
template <typename Observation, typename IsHeld>
int SplitPixels(const std::vector<Observation>& all, const std::vector<std::vector<double>>& params,
                int kind, IsHeld& is_held, std::vector<Observation>& train,
                std::vector<std::vector<double>>& train_params, std::vector<HeldPixel>& held) {
  int kept = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    Observation o = all[i];
    o.pixels.clear();
    std::vector<double> p;
    for (size_t j = 0; j < all[i].pixels.size(); ++j) {
      if (is_held()) {
        held.push_back({all[i].pixels[j], o.height_mm, kind, i});
      } else {
        o.pixels.push_back(all[i].pixels[j]);
        p.push_back(params[i][j]);
      }
    }
    if (o.pixels.empty()) continue;
    kept += static_cast<int>(o.pixels.size());
    train.push_back(std::move(o));
    train_params.push_back(std::move(p));
  }
  return kept;
}

// The training data and start of fold `fold`: every unit (point, line pixel, circle pixel,
// numbered in that order) whose number is not fold modulo `folds`; the others into `held`.
int SplitFold(const CalibrationInput& in, const FitState& s, int folds, int fold,
              CalibrationInput& train, FitState& start, std::vector<HeldPixel>& held) {
  train.points.clear();
  train.lines.clear();
  train.circles.clear();
  start.line_t.clear();
  start.circle_phi.clear();
  int unit = 0, kept = 0;
  const auto is_held = [&] { return unit++ % folds == fold; };
  for (size_t i = 0; i < in.points.size(); ++i) {
    if (is_held()) {
      held.push_back({in.points[i].pixel, in.points[i].height_mm, 0, i});
    } else {
      train.points.push_back(in.points[i]);
      ++kept;
    }
  }
  kept += SplitPixels(in.lines, s.line_t, 1, is_held, train.lines, start.line_t, held);
  kept += SplitPixels(in.circles, s.circle_phi, 2, is_held, train.circles, start.circle_phi, held);
  return kept;
}

}  // namespace

void FillHeldOut(const CalibrationInput& in, const std::vector<int>& fixed,
                 ceres::LossFunction* loss, const FitState& s, CalibrationFit& fit) {
  const int folds = in.options.holdout_folds;
  if (folds < 2) return;
  struct Sums {
    double d2 = 0.0;
    int count = 0;
  };
  std::map<double, Sums> per_plane;
  int unmappable = 0, failed = 0;
  for (int fold = 0; fold < folds; ++fold) {
    CalibrationInput train = in;
    FitState start = s;
    std::vector<HeldPixel> held;
    SplitFold(in, s, folds, fold, train, start, held);
    if (held.empty()) continue;
    if (!RefitFrom(train, fixed, loss, start)) {
      ++failed;
      continue;
    }
    const camera::CameraModel cam = camera::CameraModel::Pinhole(CameraOf(start));
    for (const HeldPixel& h : held) {
      const auto back = cam.PixelToWorld(h.pixel, h.height_mm);
      if (!back) {
        ++unmappable;
        continue;
      }
      // A point's distance has both axes of the error; a line's or circle's only the one across
      // it, counted twice for the error of a point there (isotropic, to first order).
      const double d = DistanceToTarget(in, h, *back);
      Sums& sums = per_plane[h.height_mm];
      sums.d2 += (h.kind == 0 ? 1.0 : 2.0) * d * d;
      ++sums.count;
    }
    ++fit.heldout_folds;
  }
  Sums total;
  for (PlaneResiduals& p : fit.planes) {
    const auto it = per_plane.find(p.height_mm);
    if (it == per_plane.end() || it->second.count == 0) continue;
    const Sums& sums = it->second;
    p.heldout_rms_mm = std::sqrt(sums.d2 / sums.count);
    p.heldout_count = sums.count;
    total.d2 += sums.d2;
    total.count += sums.count;
  }
  if (total.count > 0) fit.heldout_rms_mm = std::sqrt(total.d2 / total.count);
  if (failed > 0 || unmappable > 0) {
    fit.notes.push_back("warning: the held-out mapping error leaves out " + std::to_string(failed) +
                        " of " + std::to_string(folds) + " folds whose refit failed and " +
                        std::to_string(unmappable) +
                        " held-out pixels the refitted camera cannot map back");
  }
}

}  // namespace patlab::calib::internal

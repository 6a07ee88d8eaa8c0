// FitOptions::settle_px: the fit stops once the camera's image of the floor has settled. Lines
// on the floor alone leave a valley of focal length against height along which that image
// hardly changes; the solver would crawl along it to its last iteration (docs/calibrate.md).
#include <ceres/ceres.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "patlab/calib/calibrate_internal.h"
#include "patlab/camera/camera.h"
#include "patlab/core/format.h"

namespace patlab::calib::internal {
namespace {

class Settled : public ceres::IterationCallback {
 public:
  Settled(const CalibrationInput& in, const FitState& s) : s_(s), settle_px_(in.options.settle_px) {
    const camera::CameraModel start = camera::CameraModel::Pinhole(CameraOf(s));
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) {
        const Vec2 pixel((in.image_width_px - 1) * i / 4.0, (in.image_height_px - 1) * j / 4.0);
        if (const auto q = start.PixelToWorld(pixel, 0.0)) floor_.push_back(*q);
      }
    }
  }

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& it) override {
    if (!it.step_is_successful || floor_.empty()) return ceres::SOLVER_CONTINUE;
    const camera::CameraModel now = camera::CameraModel::Pinhole(CameraOf(s_));
    std::vector<Vec2> image;
    for (const Vec2& q : floor_) {
      const auto p = now.WorldToPixel(q, 0.0);
      if (!p) return ceres::SOLVER_CONTINUE;  // behind the camera: far from settled
      image.push_back(*p);
    }
    images_.push_back(std::move(image));
    if (images_.size() <= static_cast<size_t>(kSettleIterations)) return ceres::SOLVER_CONTINUE;
    const std::vector<Vec2>& then = images_[images_.size() - 1 - kSettleIterations];
    double moved = 0.0;
    for (size_t k = 0; k < then.size(); ++k)
      moved = std::max(moved, (images_.back()[k] - then[k]).norm());
    return moved <= settle_px_ ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const FitState& s_;  // the problem's parameter blocks, current every iteration
  double settle_px_;
  std::vector<Vec2> floor_;
  std::vector<std::vector<Vec2>> images_;  // one per successful iteration
};

}  // namespace

std::unique_ptr<ceres::IterationCallback> FloorImageSettled(const CalibrationInput& in,
                                                            const FitState& s) {
  return std::make_unique<Settled>(in, s);
}

std::string SettledTermination(const FitOptions& options) {
  return "SETTLED: no floor point's image moved more than " +
         FormatSignificant(options.settle_px, 3) + " px over the last " +
         std::to_string(kSettleIterations) + " successful iterations";
}

}  // namespace patlab::calib::internal

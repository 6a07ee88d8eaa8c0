// The Newton step the maximum-likelihood estimators share (estimators.cpp, gls.cpp): apply the
// step to the pose, count it, and test the step tolerances. Not installed.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "patlab/estimate/estimators.h"

namespace patlab::estimate::internal {

// Moves `pose` by `step` (x, y mm; theta rad), counts the step in `summary`, and returns whether
// the step was within `options`' step tolerances (then summary->termination is kConverged).
inline bool TakeNewtonStep(const Eigen::Vector3d& step, const Options& options, Pose2* pose,
                           Summary* summary) {
  pose->x_mm += step.x();
  pose->y_mm += step.y();
  pose->theta_rad += step.z();
  ++summary->iterations;
  if (std::abs(step.x()) <= options.step_tolerance_mm &&
      std::abs(step.y()) <= options.step_tolerance_mm &&
      std::abs(step.z()) <= options.step_tolerance_rad) {
    summary->termination = Termination::kConverged;
    return true;
  }
  return false;
}

}  // namespace patlab::estimate::internal

// The fit's residual blocks with their derivatives written out. Each pixel is one block of a few
// hundred to tens of thousands per fit, evaluated at every solver step: with Ceres' automatic
// derivatives (a Jet of 13 numbers per operation) their evaluation was a third of `patlab setup`'s
// time. The derivatives are the chain rule through the camera of camera/camera.h: world point ->
// rotation and translation -> perspective division -> radial distortion -> focal length and
// principal point. tests/calib/calibrate_costs_test.cpp checks them against central differences.
#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "patlab/calib/calibrate_internal.h"

namespace patlab::calib::internal {

namespace {

using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat3 = Eigen::Matrix3d;

Mat3 Cross(const Eigen::Vector3d& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace

bool ProjectWithDerivatives(const double* intrinsics, const double* pose, const double* world,
                            double* pixel, double* d_intrinsics, double* d_pose, double* d_world) {
  const Eigen::Map<const Eigen::Vector3d> omega(pose), w(world);
  // The rotated point as Ceres computes it (its small-angle branch included), and its
  // derivatives: by the left Jacobian of SO(3), d(R w)/d omega = -[R w]x J_l(omega) (Barfoot,
  // "State Estimation for Robotics", section 7.1.3); below Ceres' threshold it rotates by
  // w + omega x w, whose derivatives are -[w]x and I + [omega]x.
  Eigen::Vector3d rotated;
  ceres::AngleAxisRotatePoint(pose, world, rotated.data());
  const double theta2 = omega.squaredNorm();
  Mat3 d_rotated_d_omega, d_rotated_d_world;
  if (theta2 > std::numeric_limits<double>::epsilon()) {
    const double theta = std::sqrt(theta2);
    const Mat3 k = Cross(omega);
    const Mat3 left_jacobian = Mat3::Identity() + (1.0 - std::cos(theta)) / theta2 * k +
                               (theta - std::sin(theta)) / (theta2 * theta) * k * k;
    d_rotated_d_omega = -Cross(rotated) * left_jacobian;
    ceres::AngleAxisToRotationMatrix(pose, d_rotated_d_world.data());  // column-major, as Eigen
  } else {
    d_rotated_d_omega = -Cross(w);
    d_rotated_d_world = Mat3::Identity() + Cross(omega);
  }
  const Eigen::Vector3d p = rotated + Eigen::Vector3d(pose[3], pose[4], pose[5]);
  if (!(p.z() > 1e-6)) return false;  // behind the camera: the solver rejects the step
  const double f = intrinsics[0], aspect = intrinsics[1], k1 = intrinsics[4], k2 = intrinsics[5];
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const double r2 = x * x + y * y;
  const double d = 1.0 + k1 * r2 + k2 * r2 * r2;
  pixel[0] = f * x * d + intrinsics[2];
  pixel[1] = f * aspect * y * d + intrinsics[3];
  if (d_intrinsics) {  // row-major 2 x 6: f, aspect, cx, cy, k1, k2
    const double row0[6] = {x * d, 0.0, 1.0, 0.0, f * x * r2, f * x * r2 * r2};
    const double row1[6] = {aspect * y * d,          f * y * d, 0.0, 1.0, f * aspect * y * r2,
                            f * aspect * y * r2 * r2};
    for (int i = 0; i < 6; ++i) {
      d_intrinsics[i] = row0[i];
      d_intrinsics[6 + i] = row1[i];
    }
  }
  if (!d_pose && !d_world) return true;
  // pixel <- (x, y): the distortion's derivative dd/dr2 = k1 + 2 k2 r2.
  const double dd_dr2 = k1 + 2.0 * k2 * r2;
  Eigen::Matrix2d d_pixel_d_xy;
  d_pixel_d_xy << f * (d + 2.0 * x * x * dd_dr2), f * 2.0 * x * y * dd_dr2,
      f * aspect * 2.0 * x * y * dd_dr2, f * aspect * (d + 2.0 * y * y * dd_dr2);
  // (x, y) <- the point in the camera's frame.
  Mat23 d_xy_d_p;
  d_xy_d_p << 1.0 / p.z(), 0.0, -x / p.z(), 0.0, 1.0 / p.z(), -y / p.z();
  const Mat23 d_pixel_d_p = d_pixel_d_xy * d_xy_d_p;
  if (d_pose) {  // row-major 2 x 6: rotation vector, then translation
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> j(d_pose);
    j.leftCols<3>() = d_pixel_d_p * d_rotated_d_omega;
    j.rightCols<3>() = d_pixel_d_p;
  }
  if (d_world) {  // row-major 2 x 3
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> j(d_world);
    j = d_pixel_d_p * d_rotated_d_world;
  }
  return true;
}

namespace {

// A pixel against the projection of a world point that depends on kExtra nuisance unknowns
// (none for a known point): residual = projection - pixel, in px. Derived classes say where the
// point is and how it moves with those unknowns.
template <int kExtra>
class PixelCost : public ceres::CostFunction {
 public:
  static constexpr int kColumns = kExtra > 0 ? kExtra : 1;  // Eigen has no 0-column matrix
  using ExtraJacobian = Eigen::Matrix<double, 3, kColumns>;

  explicit PixelCost(const Vec2& pixel) : pixel_(pixel) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->assign({6, 6});
    if (kExtra > 0) mutable_parameter_block_sizes()->push_back(kExtra);
  }

  bool Evaluate(const double* const* parameters, double* residuals,
                double** jacobians) const final {
    const double* extra = kExtra > 0 ? parameters[2] : nullptr;
    Eigen::Vector3d world;
    ExtraJacobian d_world_d_extra;
    World(extra, world, d_world_d_extra);
    const bool want_world = kExtra > 0 && jacobians && jacobians[2];
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> d_world;
    if (!ProjectWithDerivatives(parameters[0], parameters[1], world.data(), residuals,
                                jacobians ? jacobians[0] : nullptr,
                                jacobians ? jacobians[1] : nullptr,
                                want_world ? d_world.data() : nullptr)) {
      return false;
    }
    residuals[0] -= pixel_.x();
    residuals[1] -= pixel_.y();
    if (want_world) {
      // Row-major, as Ceres lays Jacobians out (Eigen stores a single column as a column).
      constexpr int kOrder = kColumns == 1 ? Eigen::ColMajor : Eigen::RowMajor;
      Eigen::Map<Eigen::Matrix<double, 2, kColumns, kOrder>> j(jacobians[2]);
      j = d_world * d_world_d_extra;
    }
    return true;
  }

 private:
  // The world point and its derivative by the nuisance unknowns `extra` (null when kExtra is 0).
  virtual void World(const double* extra, Eigen::Vector3d& world, ExtraJacobian& d_extra) const = 0;

  Vec2 pixel_;
};

class PointCost final : public PixelCost<0> {
 public:
  PointCost(const Vec2& pixel, const Eigen::Vector3d& world) : PixelCost(pixel), world_(world) {}

 private:
  void World(const double*, Eigen::Vector3d& world, Eigen::Vector3d&) const override {
    world = world_;
  }
  Eigen::Vector3d world_;
};

// The point a fraction t of the way from `from` to `to`, at `height`.
class LineCost final : public PixelCost<1> {
 public:
  LineCost(const Vec2& pixel, const Vec2& from, const Vec2& to, double height)
      : PixelCost(pixel), from_(from), to_(to), height_(height) {}

 private:
  void World(const double* t, Eigen::Vector3d& world, Eigen::Vector3d& d_t) const override {
    const Vec2 along = to_ - from_;
    world << from_.x() + t[0] * along.x(), from_.y() + t[0] * along.y(), height_;
    d_t << along.x(), along.y(), 0.0;
  }
  Vec2 from_, to_;
  double height_;
};

// The point at angle phi on the circle, at `height`.
class CircleCost final : public PixelCost<1> {
 public:
  CircleCost(const Vec2& pixel, const Vec2& centre, double radius, double height)
      : PixelCost(pixel), centre_(centre), radius_(radius), height_(height) {}

 private:
  void World(const double* phi, Eigen::Vector3d& world, Eigen::Vector3d& d_phi) const override {
    const double c = std::cos(phi[0]), s = std::sin(phi[0]);
    world << centre_.x() + radius_ * c, centre_.y() + radius_ * s, height_;
    d_phi << -radius_ * s, radius_ * c, 0.0;
  }
  Vec2 centre_;
  double radius_, height_;
};

// A pattern's patch: its model position moved by the pattern's planar pose {x, y, theta}.
class PatternCost final : public PixelCost<3> {
 public:
  PatternCost(const Vec2& pixel, const Vec2& model, double height)
      : PixelCost(pixel), model_(model), height_(height) {}

 private:
  void World(const double* planar, Eigen::Vector3d& world, Mat3& d_planar) const override {
    const double c = std::cos(planar[2]), s = std::sin(planar[2]);
    const double mx = model_.x(), my = model_.y();
    world << planar[0] + c * mx - s * my, planar[1] + s * mx + c * my, height_;
    d_planar << 1.0, 0.0, -s * mx - c * my, 0.0, 1.0, c * mx - s * my, 0.0, 0.0, 0.0;
  }
  Vec2 model_;
  double height_;
};

// A measured camera height: (z of the camera centre - h) / sd, the centre being -R^T t. One
// residual per fit: Ceres' automatic derivatives.
struct HeightPrior {
  double height_mm, sd_mm;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    const T minus_r[3] = {-pose[0], -pose[1], -pose[2]};  // R^T = R(-r)
    const T t[3] = {pose[3], pose[4], pose[5]};
    T rt_t[3];
    ceres::AngleAxisRotatePoint(minus_r, t, rt_t);
    r[0] = (-rt_t[2] - T(height_mm)) / T(sd_mm);
    return true;
  }
};

}  // namespace

ceres::CostFunction* NewPointCost(const Vec2& pixel, const Eigen::Vector3d& world) {
  return new PointCost(pixel, world);
}

ceres::CostFunction* NewLineCost(const Vec2& pixel, const Vec2& from, const Vec2& to,
                                 double height_mm) {
  return new LineCost(pixel, from, to, height_mm);
}

ceres::CostFunction* NewCircleCost(const Vec2& pixel, const Vec2& centre, double radius_mm,
                                   double height_mm) {
  return new CircleCost(pixel, centre, radius_mm, height_mm);
}

ceres::CostFunction* NewPatternCost(const Vec2& pixel, const Vec2& model, double height_mm) {
  return new PatternCost(pixel, model, height_mm);
}

ceres::CostFunction* NewHeightPrior(double height_mm, double sd_mm) {
  return new ceres::AutoDiffCostFunction<HeightPrior, 1, 6>(new HeightPrior{height_mm, sd_mm});
}

}  // namespace patlab::calib::internal

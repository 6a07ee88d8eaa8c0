// The fit's residual blocks and their written-out derivatives (calibrate_costs.cpp): the pixel
// against the camera model of camera/camera.h, every derivative against central differences of
// the value it differentiates, at rotations large, near a half turn and below Ceres' small-angle
// threshold.
#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "patlab/calib/calibrate_internal.h"
#include "patlab/camera/camera.h"

namespace patlab::calib::internal {
namespace {

struct CostState {
  std::array<double, 6> intrinsics{};
  std::array<double, 6> pose{};
  std::array<double, 3> world{};
};

// A camera about 4 m over the floor with distortion both ways and a point in its view;
// `rotation` is its rotation vector (a half turn about an axis in the floor looks down).
CostState RandomState(std::mt19937& rng, const Eigen::Vector3d& rotation) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CostState s;
  s.intrinsics = {600.0 + 100.0 * u(rng), 1.0 + 0.05 * u(rng),  390.0 + 40.0 * u(rng),
                  290.0 + 40.0 * u(rng),  -0.2 + 0.15 * u(rng), 0.05 * u(rng)};
  for (int i = 0; i < 3; ++i) s.pose[static_cast<size_t>(i)] = rotation[i];
  // The camera centre c over the floor: t = -R c.
  const Eigen::Matrix3d r = camera::RotationFromRodrigues(rotation);
  const Eigen::Vector3d centre(500.0 * u(rng), 500.0 * u(rng), 4000.0 + 300.0 * u(rng));
  const Eigen::Vector3d t = -r * centre;
  for (int i = 0; i < 3; ++i) s.pose[static_cast<size_t>(3 + i)] = t[i];
  // A point a few degrees off the optical axis, 3-4.5 m in front of the camera.
  const Eigen::Vector3d axis = r.transpose() * Eigen::Vector3d(0.3 * u(rng), 0.3 * u(rng), 1.0);
  const Eigen::Vector3d point = centre + (3750.0 + 750.0 * u(rng)) * axis;
  s.world = {point.x(), point.y(), point.z()};
  return s;
}

// The rotation vectors of the cases: a camera looking down (a half turn about an axis in the
// floor), others at random, one barely rotated (Ceres' small-angle branch) and one near a half
// turn about a tilted axis.
std::vector<Eigen::Vector3d> Rotations(std::mt19937& rng) {
  std::vector<Eigen::Vector3d> out = {Eigen::Vector3d(3.1, 0.2, -0.1),
                                      Eigen::Vector3d(0.0, 3.14159, 0.0),
                                      Eigen::Vector3d(3.0e-9, -2.0e-9, 1.0e-9)};
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    Eigen::Vector3d v(n(rng), n(rng), n(rng));
    out.push_back(v.normalized() * (0.2 + 2.9 * std::abs(n(rng)) / 3.0));
  }
  return out;
}

Vec2 Pixel(const CostState& s) {
  double p[2];
  EXPECT_TRUE(ProjectWithDerivatives(s.intrinsics.data(), s.pose.data(), s.world.data(), p, nullptr,
                                     nullptr, nullptr));
  return {p[0], p[1]};
}

// Central differences of `f` by parameter `i` of `x` (step relative to its size), against the
// analytic column `analytic` (two rows, stride `stride`, column `i`).
void ExpectDerivative(const std::function<Vec2()>& f, double& x, const double* analytic, int stride,
                      int i, const char* what) {
  const double h = 1e-6 * std::max(1.0, std::abs(x)), x0 = x;
  x = x0 + h;
  const Vec2 plus = f();
  x = x0 - h;
  const Vec2 minus = f();
  x = x0;
  const Vec2 numeric = (plus - minus) / (2.0 * h);
  for (int row = 0; row < 2; ++row) {
    const double a = analytic[row * stride + i], n = numeric[row];
    EXPECT_NEAR(a, n, 1e-5 * std::max(1.0, std::abs(n))) << what << " row " << row << " col " << i;
  }
}

TEST(CalibrateCosts, TheProjectionIsTheCameraModels) {
  std::mt19937 rng(7);
  for (const Eigen::Vector3d& rotation : Rotations(rng)) {
    const CostState s = RandomState(rng, rotation);
    FitState fs;
    fs.intrinsics = s.intrinsics;
    fs.pose = s.pose;
    const std::optional<Vec2> expected =
        camera::CameraModel::Pinhole(CameraOf(fs))
            .WorldToPixel(Vec2(s.world[0], s.world[1]), s.world[2]);
    ASSERT_TRUE(expected.has_value());
    const Vec2 p = Pixel(s);
    EXPECT_NEAR(p.x(), expected->x(), 1e-6) << rotation.transpose();
    EXPECT_NEAR(p.y(), expected->y(), 1e-6) << rotation.transpose();
  }
}

TEST(CalibrateCosts, DerivativesAreTheCentralDifferences) {
  std::mt19937 rng(11);
  for (const Eigen::Vector3d& rotation : Rotations(rng)) {
    CostState s = RandomState(rng, rotation);
    double p[2], d_intrinsics[12], d_pose[12], d_world[6];
    ASSERT_TRUE(ProjectWithDerivatives(s.intrinsics.data(), s.pose.data(), s.world.data(), p,
                                       d_intrinsics, d_pose, d_world));
    const auto f = [&] { return Pixel(s); };
    for (int i = 0; i < 6; ++i) {
      ExpectDerivative(f, s.intrinsics[static_cast<size_t>(i)], d_intrinsics, 6, i, "intrinsics");
      ExpectDerivative(f, s.pose[static_cast<size_t>(i)], d_pose, 6, i, "pose");
    }
    for (int i = 0; i < 3; ++i)
      ExpectDerivative(f, s.world[static_cast<size_t>(i)], d_world, 3, i, "world");
  }
}

TEST(CalibrateCosts, APointBehindTheCameraIsRejected) {
  std::mt19937 rng(3);
  CostState s = RandomState(rng, Eigen::Vector3d(3.1, 0.0, 0.0));  // looking down
  s.world[2] = 5000.0;                                             // above the camera
  double p[2];
  EXPECT_FALSE(ProjectWithDerivatives(s.intrinsics.data(), s.pose.data(), s.world.data(), p,
                                      nullptr, nullptr, nullptr));
}

// Every block's residual is the projection of its world point minus the observed pixel, and its
// Jacobians (the nuisance unknowns' included) are the central differences of that residual.
TEST(CalibrateCosts, EachBlockIsTheProjectionMinusThePixelWithItsJacobians) {
  std::mt19937 rng(5);
  const Vec2 observed(301.5, 244.25);
  for (const Eigen::Vector3d& rotation : Rotations(rng)) {
    CostState s = RandomState(rng, rotation);
    const Vec2 at(s.world[0], s.world[1]);
    const double height = s.world[2];
    struct Case {
      const char* name;
      std::unique_ptr<ceres::CostFunction> cost;
      std::vector<double> extra;
      Vec2 world;  // where the extra unknowns put the point
    };
    std::vector<Case> cases;
    cases.push_back({"point",
                     std::unique_ptr<ceres::CostFunction>(
                         NewPointCost(observed, Eigen::Vector3d(at.x(), at.y(), height))),
                     {},
                     at});
    // The line from `at` - (300, 100) to `at` + (900, 300): t = 0.25 is `at`.
    cases.push_back({"line",
                     std::unique_ptr<ceres::CostFunction>(
                         NewLineCost(observed, at - Vec2(300, 100), at + Vec2(900, 300), height)),
                     {0.25},
                     at});
    // The circle of radius 500 mm round `at` - (500 cos 0.7, 500 sin 0.7): phi = 0.7 is `at`.
    cases.push_back({"circle",
                     std::unique_ptr<ceres::CostFunction>(NewCircleCost(
                         observed, at - 500.0 * Vec2(std::cos(0.7), std::sin(0.7)), 500.0, height)),
                     {0.7},
                     at});
    // A patch at (40, -25) mm in its pattern, the pattern at `at` - R(0.4) (40, -25), turned 0.4.
    const Vec2 model(40.0, -25.0);
    const Vec2 turned(std::cos(0.4) * model.x() - std::sin(0.4) * model.y(),
                      std::sin(0.4) * model.x() + std::cos(0.4) * model.y());
    cases.push_back({"pattern",
                     std::unique_ptr<ceres::CostFunction>(NewPatternCost(observed, model, height)),
                     {at.x() - turned.x(), at.y() - turned.y(), 0.4},
                     at});
    const Vec2 expected = Pixel(s) - observed;
    for (Case& c : cases) {
      std::vector<double*> blocks = {s.intrinsics.data(), s.pose.data()};
      if (!c.extra.empty()) blocks.push_back(c.extra.data());
      double r[2];
      std::vector<double> j0(12), j1(12), j2(2 * c.extra.size() + 1);
      double* jacobians[3] = {j0.data(), j1.data(), j2.data()};
      ASSERT_TRUE(c.cost->Evaluate(blocks.data(), r, jacobians)) << c.name;
      EXPECT_NEAR(r[0], expected.x(), 1e-7) << c.name;
      EXPECT_NEAR(r[1], expected.y(), 1e-7) << c.name;
      const auto f = [&] {
        double out[2];
        EXPECT_TRUE(c.cost->Evaluate(blocks.data(), out, nullptr));
        return Vec2(out[0], out[1]);
      };
      for (int i = 0; i < 6; ++i) {
        ExpectDerivative(f, s.intrinsics[static_cast<size_t>(i)], j0.data(), 6, i, c.name);
        ExpectDerivative(f, s.pose[static_cast<size_t>(i)], j1.data(), 6, i, c.name);
      }
      const int n = static_cast<int>(c.extra.size());
      for (int i = 0; i < n; ++i)
        ExpectDerivative(f, c.extra[static_cast<size_t>(i)], j2.data(), n, i, c.name);
      // Without the Jacobians asked for, the same residual.
      double bare[2];
      ASSERT_TRUE(c.cost->Evaluate(blocks.data(), bare, nullptr));
      EXPECT_EQ(bare[0], r[0]);
      EXPECT_EQ(bare[1], r[1]);
    }
  }
}

// A camera height's prior: (height of the camera centre - measured) / sd.
TEST(CalibrateCosts, TheHeightPriorIsTheCentresHeightAgainstTheMeasuredOne) {
  std::mt19937 rng(9);
  const CostState s = RandomState(rng, Eigen::Vector3d(3.0, 0.3, -0.2));
  FitState fs;
  fs.intrinsics = s.intrinsics;
  fs.pose = s.pose;
  const camera::PinholeCamera c = CameraOf(fs);
  const double centre_z = (-c.rotation.transpose() * c.translation_mm).z();
  const std::unique_ptr<ceres::CostFunction> prior(NewHeightPrior(4000.0, 50.0));
  const double* blocks[1] = {s.pose.data()};
  double r = 0.0;
  ASSERT_TRUE(prior->Evaluate(blocks, &r, nullptr));
  EXPECT_NEAR(r, (centre_z - 4000.0) / 50.0, 1e-9);
}

}  // namespace
}  // namespace patlab::calib::internal

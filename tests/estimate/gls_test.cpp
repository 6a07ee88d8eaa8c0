// Generalised least squares (estimate/gls.h) against an independent brute-force maximum of the
// Gaussian likelihood, and its Cramer-Rao bound against an independent Fisher information.
#include "patlab/estimate/gls.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "../test_util.h"

namespace patlab::estimate {
namespace {

using testing::kPi;
using Matrix = Eigen::MatrixXd;

// The covariance A of gls.h built directly with std::exp and Eigen (no shared code).
Matrix Covariance(const Pattern& pattern, const GaussianNoise& noise) {
  const int n = pattern.size();
  Matrix a = Matrix::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double d = (pattern.patches[i].position_mm - pattern.patches[j].position_mm).norm();
      const double c = noise.correlation_length_mm > 0.0
                           ? std::exp(-d / noise.correlation_length_mm)
                           : (i == j ? 1.0 : 0.0);
      const double g2 = noise.common_sigma_ratio * noise.common_sigma_ratio;
      a(2 * i, 2 * j) = c + g2;
      a(2 * i + 1, 2 * j + 1) = c * noise.sigma_y_ratio * noise.sigma_y_ratio + g2;
    }
  }
  return a;
}

Pattern RandomLayout(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> coordinate(-90.0, 90.0);
  Pattern p;
  p.name = "random";
  for (int i = 0; i < n; ++i) {
    Patch patch;
    patch.position_mm = Vec2(coordinate(rng), coordinate(rng));
    patch.radius_mm = 5.0;
    p.patches.push_back(patch);
  }
  p.patches[0].role = PatchRole::kKey;
  p.orientation_pairs = DefaultOrientationPairs(p.patches, 0);
  return p;
}

// The profile cost of the heading: for fixed theta the best translation is the weighted mean
// t = (S^T W S)^-1 S^T W (v - R p) (S stacks 2x2 identities), and the cost e^T W e there.
double ProfileCost(const Pattern& pattern, const Matrix& w, const std::vector<Vec2>& v,
                   double theta, Vec2* translation) {
  const int n = pattern.size();
  Eigen::VectorXd d(2 * n);
  Matrix s = Matrix::Zero(2 * n, 2);
  for (int i = 0; i < n; ++i) {
    const Vec2 rp = Eigen::Rotation2Dd(theta) * pattern.patches[i].position_mm;
    d.segment<2>(2 * i) = v[i] - rp;
    s(2 * i, 0) = s(2 * i + 1, 1) = 1.0;
  }
  const Vec2 t = (s.transpose() * w * s).ldlt().solve(s.transpose() * w * d);
  const Eigen::VectorXd e = d - s * t;
  *translation = t;
  return e.dot(w * e);
}

// The global maximum of the likelihood by brute force: the profile cost on 7200 headings, then
// golden-section search around the best to 1e-13 rad.
Pose2 BruteForceMaximum(const Pattern& pattern, const Matrix& w, const std::vector<Vec2>& v) {
  Vec2 t;
  double best = 0.0, best_cost = INFINITY;
  constexpr int kGrid = 7200;
  for (int k = 0; k < kGrid; ++k) {
    const double theta = -kPi + 2.0 * kPi * k / kGrid;
    const double cost = ProfileCost(pattern, w, v, theta, &t);
    if (cost < best_cost) best_cost = cost, best = theta;
  }
  double lo = best - 2.0 * kPi / kGrid, hi = best + 2.0 * kPi / kGrid;
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  while (hi - lo > 1e-13) {
    const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
    if (ProfileCost(pattern, w, v, a, &t) < ProfileCost(pattern, w, v, b, &t)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  const double theta = (lo + hi) / 2.0;
  ProfileCost(pattern, w, v, theta, &t);
  return {t.x(), t.y(), WrapAngle(theta)};
}

TEST(GeneralisedLeastSquares, IsTheBruteForceLikelihoodMaximumOnRandomLayoutsAndCovariances) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> ratio(0.3, 3.0), length(0.0, 200.0), common(0.0, 1.0);
  std::uniform_real_distribution<double> heading(-kPi, kPi), where(-1000.0, 1000.0);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 60; ++trial) {
    const Pattern pattern = RandomLayout(rng, 3 + trial % 6);
    GaussianNoise noise{ratio(rng), trial % 3 == 0 ? 0.0 : length(rng),
                        trial % 2 == 0 ? 0.0 : common(rng)};
    if (trial % 5 == 0) noise.sigma_y_ratio = 1.0;  // correlation or offset alone
    const Model model = Model::FromPattern(pattern);
    const Matrix a = Covariance(pattern, noise);
    const Matrix w = a.inverse();
    // Noise drawn with the covariance itself, sigma 2 mm.
    const Eigen::VectorXd z =
        Eigen::VectorXd::NullaryExpr(2 * pattern.size(), [&] { return normal(rng); });
    const Eigen::VectorXd e = 2.0 * Matrix(a.llt().matrixL()) * z;
    const Pose2 truth{where(rng), where(rng), heading(rng)};
    std::vector<Vec2> v(pattern.size());
    for (int i = 0; i < pattern.size(); ++i)
      v[i] = truth.Apply(model.model_mm[i]) + e.segment<2>(2 * i);
    const GaussianWeights weights = GaussianWeights::Make(model, noise);
    Summary summary;
    const Pose2 got = GeneralisedLeastSquares(model, weights, v.data(),
                                              LeastSquares(model, v.data()), Options{}, &summary);
    const Pose2 want = BruteForceMaximum(pattern, w, v);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(summary.termination, Termination::kConverged);
    EXPECT_NEAR(got.x_mm, want.x_mm, 1e-6);
    EXPECT_NEAR(got.y_mm, want.y_mm, 1e-6);
    EXPECT_NEAR(WrapAngle(got.theta_rad - want.theta_rad), 0.0, 1e-6);
    // The weights are A^-1.
    for (int r = 0; r < 2 * pattern.size(); ++r) {
      for (int c = 0; c < 2 * pattern.size(); ++c) {
        EXPECT_NEAR(weights(r, c), w(r, c), 1e-9 * w.cwiseAbs().maxCoeff());
      }
    }
  }
}

TEST(GeneralisedLeastSquares, IsLeastSquaresUnderIsotropicNoise) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  const GaussianWeights weights = GaussianWeights::Make(model, GaussianNoise{});
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 3.0);
  std::array<Vec2, kMaxPatches> v{};
  const Pose2 truth{100.0, -50.0, 2.5};
  for (int i = 0; i < model.num_patches; ++i) {
    v[i] = truth.Apply(model.model_mm[i]) + Vec2(noise(rng), noise(rng));
  }
  const Pose2 gls =
      GeneralisedLeastSquares(model, weights, v.data(), Fast(model, v.data()), Options{}, nullptr);
  const Pose2 lsq = LeastSquares(model, v.data());
  EXPECT_NEAR(gls.x_mm, lsq.x_mm, 1e-9);
  EXPECT_NEAR(gls.y_mm, lsq.y_mm, 1e-9);
  EXPECT_NEAR(WrapAngle(gls.theta_rad - lsq.theta_rad), 0.0, 1e-11);
}

// The bound from an independent information J^T A^-1 J (Eigen, analytic J), averaged over 1000
// headings.
StdPerSigma IndependentBound(const Pattern& pattern, const GaussianNoise& noise) {
  const Matrix w = Covariance(pattern, noise).inverse();
  const int n = pattern.size();
  double position = 0.0, theta = 0.0;
  constexpr int kHeadings = 1000;
  for (int k = 0; k < kHeadings; ++k) {
    const double phi = 2.0 * kPi * (k + 0.5) / kHeadings;
    Matrix j = Matrix::Zero(2 * n, 3);
    for (int i = 0; i < n; ++i) {
      const Vec2 p = pattern.patches[i].position_mm;
      j(2 * i, 0) = j(2 * i + 1, 1) = 1.0;
      j(2 * i, 2) = -std::sin(phi) * p.x() - std::cos(phi) * p.y();
      j(2 * i + 1, 2) = std::cos(phi) * p.x() - std::sin(phi) * p.y();
    }
    const Eigen::Matrix3d cov = (j.transpose() * w * j).inverse();
    position += (cov(0, 0) + cov(1, 1)) / 2.0;
    theta += cov(2, 2);
  }
  return {std::sqrt(position / kHeadings), std::sqrt(theta / kHeadings)};
}

TEST(GaussianCramerRaoBound, IsTheIndependentFisherInformationsBound) {
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Pattern pattern = testing::ShippedPattern(name);
    const Model model = Model::FromPattern(pattern);
    // A = I: the closed form of bounds.h.
    const StdPerSigma iso = GaussianCramerRaoBound(model, GaussianWeights::Make(model, {}));
    EXPECT_NEAR(iso.position_per_axis, CramerRaoBound(model).position_per_axis, 1e-12) << name;
    EXPECT_NEAR(iso.theta, CramerRaoBound(model).theta, 1e-12) << name;
    for (const GaussianNoise& noise : {GaussianNoise{2.5, 0.0, 0.0}, GaussianNoise{1.0, 80.0, 0.0},
                                       GaussianNoise{0.5, 40.0, 0.7}}) {
      const StdPerSigma got = GaussianCramerRaoBound(model, GaussianWeights::Make(model, noise));
      const StdPerSigma want = IndependentBound(pattern, noise);
      EXPECT_NEAR(got.position_per_axis, want.position_per_axis, 1e-9 * want.position_per_axis)
          << name;
      EXPECT_NEAR(got.theta, want.theta, 1e-9 * want.theta) << name;
    }
  }
}

}  // namespace
}  // namespace patlab::estimate

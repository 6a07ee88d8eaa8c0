// Tests of the one sampled Gaussian kernel (src/patlab/core/gaussian.h).
#include "patlab/core/gaussian.h"

#include <gtest/gtest.h>

#include <cmath>

namespace patlab {
namespace {

TEST(GaussianHalfKernel, MatchesTheNormalisedSampledGaussian) {
  // sigma 1.5, truncate 4: radius floor(6.5) = 6; w[k] proportional to exp(-k^2 / 4.5).
  const std::vector<double> w = GaussianHalfKernel(1.5, 4.0);
  ASSERT_EQ(w.size(), 7u);
  double sum = 0.0;
  for (int k = -6; k <= 6; ++k) sum += std::exp(-k * k / 4.5);
  for (int k = 0; k <= 6; ++k) EXPECT_NEAR(w[k], std::exp(-k * k / 4.5) / sum, 1e-15);
  double total = w[0];
  for (size_t k = 1; k < w.size(); ++k) total += 2.0 * w[k];
  EXPECT_NEAR(total, 1.0, 1e-15);
  // scipy 1.10 scipy.ndimage._filters._gaussian_kernel1d(1.5, 0, 6)[6], the centre tap.
  EXPECT_NEAR(w[0], 0.2659642571610709, 1e-15);
}

TEST(GaussianHalfKernel, RadiusZeroIsTheIdentity) {
  EXPECT_EQ(GaussianHalfKernel(0.0, 4.0), std::vector<double>{1.0});
  EXPECT_EQ(GaussianHalfKernel(0.1, 4.0), std::vector<double>{1.0});  // floor(0.9) = 0
  EXPECT_EQ(GaussianHalfKernel(0.2, 4.0).size(), 2u);                 // floor(1.3) = 1
}

}  // namespace
}  // namespace patlab

#include "patlab/core/gaussian.h"

#include <cmath>
#include <cstddef>

#include "patlab/core/error.h"

namespace patlab {

std::vector<double> GaussianHalfKernel(double sigma, double truncate_sigmas) {
  PATLAB_CHECK(std::isfinite(sigma) && sigma >= 0.0);
  PATLAB_CHECK(std::isfinite(truncate_sigmas) && truncate_sigmas > 0.0);
  const auto radius = static_cast<std::ptrdiff_t>(truncate_sigmas * sigma + 0.5);
  if (radius == 0) return {1.0};
  std::vector<double> w(static_cast<std::size_t>(radius) + 1);
  double sum = 0.0;
  for (std::ptrdiff_t k = -radius; k <= radius; ++k) {
    const double v = std::exp(-0.5 / (sigma * sigma) * static_cast<double>(k * k));
    sum += v;
    if (k >= 0) w[static_cast<std::size_t>(k)] = v;
  }
  for (double& v : w) v /= sum;
  return w;
}

}  // namespace patlab

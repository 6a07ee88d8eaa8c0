#include "patlab/estimate/mixture_bound.h"

#include <algorithm>
#include <cmath>

#include "patlab/core/portable_math.h"

namespace patlab::estimate {

double MixtureLocationInformation(double outlier_probability, double outlier_sigma_ratio) {
  const double p = outlier_probability, k2 = outlier_sigma_ratio * outlier_sigma_ratio;
  // pi r^3 w^2 f with the 2-D densities' 1 / (2 pi s^2) kept.
  const auto integrand = [p, k2](double r) {
    const double inlier = (1.0 - p) * pmath::Exp(-r * r / 2.0) / (2.0 * std::numbers::pi);
    const double outlier = p * pmath::Exp(-r * r / (2.0 * k2)) / (2.0 * std::numbers::pi * k2);
    const double f = inlier + outlier;
    if (!(f > 0.0)) return 0.0;
    const double score = (inlier + outlier / k2) / f;  // w(r): -f'(r) / (r f(r))
    return std::numbers::pi * r * r * r * score * score * f;
  };
  // Composite Simpson on [0, 40] (the inliers' scale) and on [40, 40 k] (the outliers'), 20000
  // intervals each: both components' curvature resolved.
  const auto simpson = [&integrand](double from, double to) {
    constexpr int kIntervals = 20000;  // even
    const double h = (to - from) / kIntervals;
    double sum = integrand(from) + integrand(to);
    for (int j = 1; j < kIntervals; ++j) {
      sum += (j % 2 == 1 ? 4.0 : 2.0) * integrand(from + j * h);
    }
    return sum * h / 3.0;
  };
  const double k = std::sqrt(k2);
  return simpson(0.0, 40.0) + (k > 1.0 ? simpson(40.0, 40.0 * k) : 0.0);
}

StdPerSigma MixtureCramerRaoBound(const Model& model, double outlier_probability,
                                  double outlier_sigma_ratio) {
  const double information = MixtureLocationInformation(outlier_probability, outlier_sigma_ratio);
  StdPerSigma bound = CramerRaoBound(model);
  bound.position_per_axis /= std::sqrt(information);
  bound.theta /= std::sqrt(information);
  return bound;
}

}  // namespace patlab::estimate

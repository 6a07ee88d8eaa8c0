#include "patlab/stats/noncentral_chi2.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::stats {

double NoncentralChiSquaredCdf(double x, double dof, double lambda) {
  if (!(dof > 0.0) || !(lambda >= 0.0) || !(x >= 0.0) || !std::isfinite(dof + lambda + x)) {
    throw InputError(std::string("noncentral chi-square: dof ") + FormatNumber(dof) + ", lambda " +
                     FormatNumber(lambda) + ", x " + FormatNumber(x) +
                     "; expected finite dof > 0, lambda >= 0 and x >= 0");
  }
  if (lambda == 0.0) return boost::math::cdf(boost::math::chi_squared(dof), x);
  return boost::math::cdf(boost::math::non_central_chi_squared(dof, lambda), x);
}

double NoncentralityForCdf(double dof, double x, double p) {
  if (!(dof > 0.0) || !(x > 0.0) || !std::isfinite(dof + x)) {
    throw InputError(std::string("noncentral chi-square: dof ") + FormatNumber(dof) + ", x " +
                     FormatNumber(x) + "; expected finite dof > 0 and x > 0");
  }
  const double central = boost::math::cdf(boost::math::chi_squared(dof), x);
  if (!(p > 0.0) || !(p < central)) {
    throw InputError(std::string("noncentral chi-square: p is ") + FormatNumber(p) +
                     "; expected 0 < p < " + FormatNumber(central) +
                     " (the central chi-square's P(X <= x))");
  }
  return boost::math::non_central_chi_squared::find_non_centrality(dof, x, p);
}

}  // namespace patlab::stats

// The noncentral chi-square distribution (Boost.Math's non_central_chi_squared): the law of
// |x|^2 for x ~ N(mu, I_dof), with noncentrality lambda = |mu|^2. patlab uses it for the rotation
// fix of a pattern (design/compare.h): the rigid-fit error of a wrong rotation, divided by the
// patch variance, is noncentral chi-square with 2m - 3 degrees of freedom and noncentrality
// E0 / sigma^2.
#pragma once

namespace patlab::stats {

// P(X <= x) for X ~ chi'^2(dof, lambda); dof > 0, lambda >= 0, x >= 0.
double NoncentralChiSquaredCdf(double x, double dof, double lambda);

// The noncentrality lambda at which P(X <= x) = p for X ~ chi'^2(dof, lambda) (the cdf falls as
// lambda grows); dof > 0, x > 0, 0 < p < P(chi^2(dof) <= x). InputError naming the argument
// otherwise.
double NoncentralityForCdf(double dof, double x, double p);

}  // namespace patlab::stats

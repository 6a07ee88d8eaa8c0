// The Cramer-Rao bound under the outlier mixture of sim/noise.h: each patch error is
// N(0, sigma^2 I) with probability 1 - p and N(0, k^2 sigma^2 I) with probability p,
// independently.
//
// A patch's density f is isotropic, so its location Fisher information is i(p, k) / sigma^2 times
// the identity (by symmetry), with, in units of sigma and r = |e|,
//
//   i(p, k) = 1/2 E[(f'(r) / f(r))^2] = pi * integral_0^inf r^3 w(r)^2 f(r) dr,
//   w(r) = ((1 - p) phi_1(r) + p phi_k(r) / k^2) / f(r),  f = (1 - p) phi_1 + p phi_k,
//
// phi_s the 2-D normal density of std s (E[(x / r)^2] = 1/2 splits the radial score over the two
// axes). i(0, k) = i(p, 1) = 1, and 1 / (1 - p + p k^2) <= i <= 1 - p + p / k^2: the Gaussian of
// the mixture's variance has the least information of all densities of that variance (the lower
// limit, which least squares attains), and knowing which patches are outliers could only add
// information (the upper). The pose's information is then i / sigma^2 J^T J: the isotropic bound
// (bounds.h) divided by sqrt(i).
#pragma once

#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"

namespace patlab::estimate {

// i(p, k) by composite Simpson's rule, 20000 intervals on r in [0, 40] and as many on [40, 40 k]
// when k > 1 (the integrand is smooth and negligible beyond; the rule's error is below 1e-12
// here). p in [0, 1), k > 0.
double MixtureLocationInformation(double outlier_probability, double outlier_sigma_ratio);

// The bound per unit sigma under the mixture: CramerRaoBound(model) / sqrt(i(p, k)).
StdPerSigma MixtureCramerRaoBound(const Model& model, double outlier_probability,
                                  double outlier_sigma_ratio);

}  // namespace patlab::estimate

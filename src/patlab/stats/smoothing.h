// Smoothing of a tracked series and the residuals around it: the paper's error estimate for a
// track without ground truth (Bruce & Veloso 2003, section II: "smoothing the data with a large
// Gaussian kernel (sigma = 10) and then comparing single samples with the smoothed version"),
// and the lag-k autocorrelation of such residuals (section V, Fig. 6).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "patlab/core/options.h"

namespace patlab::stats {

struct SmoothingOptions {
  // Kernel standard deviation in samples (not time or mm). The paper uses 10. 0 returns the
  // input unchanged. Larger values follow slow motion less closely, leaving more of it in the
  // residuals; smaller values absorb part of the noise into the "signal".
  double sigma_samples = 10.0;
  // The kernel is cut at radius floor(truncate_sigmas * sigma_samples + 0.5) samples and
  // renormalised to sum 1 (scipy.ndimage.gaussian_filter1d's truncate).
  double truncate_sigmas = 4.0;
};
// sigma_samples a finite number >= 0, truncate_sigmas a finite number > 0 (core/options.h).
std::vector<OptionsProblem> Check(const SmoothingOptions& options);
void Validate(const SmoothingOptions& options);

// The smoothing kernel, one half of it: w[k] = exp(-k^2 / (2 sigma^2)) / sum for k = 0..radius,
// sum over |k| <= radius so that w[0] + 2 sum_{k>=1} w[k] = 1 (scipy _gaussian_kernel1d).
// {1} when the radius is 0. Validates first.
std::vector<double> GaussianKernel(const SmoothingOptions& options);

// Gaussian-smoothed series, same length as x. Boundary: reflection about the edge including the
// edge sample (d c b a | a b c d | d c b a), repeated as needed; this is
// scipy.ndimage.gaussian_filter1d(x, sigma, mode='reflect', truncate=4.0), hand-written because
// no packaged C++ library here offers exactly this filter. x must be non-empty and finite.
std::vector<double> GaussianSmooth(std::span<const double> x, const SmoothingOptions& options = {});

// x - GaussianSmooth(x): the per-sample error estimate of section II.
std::vector<double> SmoothingResiduals(std::span<const double> x,
                                       const SmoothingOptions& options = {});

// White-noise factor of the section II error estimate: for iid errors of std s, the residual
// x - GaussianSmooth(x) has std s * sqrt(1 - 2 w_0 + sum_k w_k^2) away from the ends, w the
// kernel above (0.974 for sigma = 10), since Var(e - w * e) = s^2 (1 - 2 w_0 + sum w_k^2).
// 0 when the radius is 0 (the residual is then exactly 0).
double ResidualStdFactor(const SmoothingOptions& options);

// White-noise autocorrelation of those residuals at lag k >= 1: with c = delta - w (w the full
// symmetric kernel, zero beyond its radius), Cov(r_t, r_t+k) = s^2 sum_j c_j c_j+k, so
//   rho_k = (-2 w_k + sum_j w_j w_j+k) / (1 - 2 w_0 + sum_j w_j^2)
// (-0.054 at k = 1 for sigma = 10): what the lag-k autocorrelation of residuals of uncorrelated
// errors is, away from the ends. 0 when the radius is 0.
double ResidualAutocorrelation(const SmoothingOptions& options, std::size_t lag);

// Sample autocorrelation at lag k (Box & Jenkins; what statsmodels.tsa.acf returns):
//   r_k = sum_{t<n-k} (x_t - m)(x_{t+k} - m) / sum_t (x_t - m)^2,  m = mean(x).
// Needs lag < n (InputError otherwise); a constant series gives NaN.
double Autocorrelation(std::span<const double> x, std::size_t lag);

}  // namespace patlab::stats

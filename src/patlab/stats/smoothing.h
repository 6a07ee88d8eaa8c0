// Smoothing of a tracked series and the residuals around it: the paper's error estimate for a
// track without ground truth (Bruce & Veloso 2003, section II: "smoothing the data with a large
// Gaussian kernel (sigma = 10) and then comparing single samples with the smoothed version"),
// and the lag-k autocorrelation of such residuals (section V, Fig. 6).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

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
// Throws InputError naming the field unless sigma_samples >= 0 and truncate_sigmas > 0, finite.
void Validate(const SmoothingOptions& options);

// Gaussian-smoothed series, same length as x. Boundary: reflection about the edge including the
// edge sample (d c b a | a b c d | d c b a), repeated as needed; this is
// scipy.ndimage.gaussian_filter1d(x, sigma, mode='reflect', truncate=4.0), hand-written because
// no packaged C++ library here offers exactly this filter. x must be non-empty and finite.
std::vector<double> GaussianSmooth(std::span<const double> x, const SmoothingOptions& options = {});

// x - GaussianSmooth(x): the per-sample error estimate of section II.
std::vector<double> SmoothingResiduals(std::span<const double> x,
                                       const SmoothingOptions& options = {});

// Sample autocorrelation at lag k (Box & Jenkins; what statsmodels.tsa.acf returns):
//   r_k = sum_{t<n-k} (x_t - m)(x_{t+k} - m) / sum_t (x_t - m)^2,  m = mean(x).
// Needs lag < n (InputError otherwise); a constant series gives NaN.
double Autocorrelation(std::span<const double> x, std::size_t lag);

}  // namespace patlab::stats

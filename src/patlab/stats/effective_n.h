// Effective sample size of a standard deviation estimated from an autocorrelated series
// (consecutive frames of a track are correlated: a pattern moves a fifth of a pixel per frame, so
// its quantisation error repeats), and the std interval with it.
//
// For a stationary Gaussian series with autocorrelation rho_k the sample variance has
//   Var(s^2) = 2 sigma^4 / n * tau,   tau = 1 + 2 sum_{k >= 1} rho_k^2
// (Bartlett 1946, J. R. Stat. Soc. Suppl. 8:27; Priestley 1981, eq. 5.3.22), so the chi-square
// interval of the std holds with n / tau degrees of freedom instead of n. For an AR(1) series
// x_t = phi x_{t-1} + e_t, rho_k = phi^k and tau = (1 + phi^2) / (1 - phi^2).
//
// tau is estimated from the sample autocorrelations r_k of the deviations from each segment's
// own mean (several runs pooled), summed over lags 1 .. K: K is the last lag before the first
// |r_k| < 2 / sqrt(n) (inside the white-noise band, where the estimates are noise; Bartlett's
// cut-off), at most max_lag. Each r_k^2 then carries a bias of about 1 / n, so tau is good to
// about 2K / n.
#pragma once

#include <span>

#include "patlab/stats/summary.h"

namespace patlab::stats {

struct EffectiveSize {
  double tau = 1.0;      // variance inflation 1 + 2 sum r_k^2, >= 1
  int lags = 0;          // K, the lags summed
  double n = 0.0;        // samples in all segments
  double dof = 0.0;      // n - segments: the dof of the pooled std about each segment's mean
  double dof_eff = 0.0;  // dof / tau
  double lag1 = 0.0;     // r_1 (NaN when no segment has 2 samples)
};

// tau of several segments (each about its own mean), the autocorrelations pooled over segments:
// r_k = sum_seg sum_t d_t d_{t+k} / sum_seg sum_t d_t^2. Segments with fewer than 2 samples are
// skipped. max_lag >= 1 (InputError otherwise); values must be finite. A constant series or no
// usable segment: tau 1, lags 0, dof as computed (possibly 0).
// min_lags >= 0: lags summed whatever the band (a detrending whose residuals are correlated
// over a known reach, e.g. 2 radius for a smoothing kernel of that radius, whose autocorrelation
// crosses zero inside it), at most max_lag; such a lag inside the band adds r_k^2 - 1 / n (the
// noise floor of r_k^2 taken off), and tau is at least 1.
EffectiveSize VarianceEffectiveSize(std::span<const std::span<const double>> segments,
                                    int max_lag = 1000, int min_lags = 0);

// The chi-square interval of a std with dof / tau degrees of freedom (StdConfidenceInterval).
StdWithCi StdIntervalEffective(double std, const EffectiveSize& size, double level = 0.95);

}  // namespace patlab::stats

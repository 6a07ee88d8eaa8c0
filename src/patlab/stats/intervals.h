// Confidence intervals for counts: a proportion (Wilson score) and a Poisson rate (Garwood exact).
// Used by the detect-mode runner and the design reports for detection and misidentification rates.
#pragma once

#include <cstdint>

namespace patlab::stats {

// A proportion k / n with its 95% Wilson score interval (Wilson 1927, JASA 22:209):
//   centre = (p + z^2 / 2n) / (1 + z^2 / n),
//   half   = z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / 4n^2),   p = k / n, z = 1.959964.
// Unlike the normal interval it stays inside [0, 1] and is not empty at k = 0 or k = n.
// n = 0: rate and interval NaN.
struct Proportion {
  int64_t count = 0;
  int64_t total = 0;
  double rate = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};
Proportion WilsonInterval(int64_t count, int64_t total);

// A Poisson mean per unit (events per frame) with its exact 95% interval (Garwood 1936):
//   lower = chi2_{2K}^-1(0.025) / 2F, upper = chi2_{2K+2}^-1(0.975) / 2F, K events in F frames
// (lower = 0 when K = 0).
struct PoissonRate {
  int64_t count = 0;
  int64_t frames = 0;
  double rate = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};
PoissonRate GarwoodInterval(int64_t count, int64_t frames);

}  // namespace patlab::stats

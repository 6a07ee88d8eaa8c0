// The one sampled Gaussian kernel, shared by the track analysis's smoothing (stats/smoothing.h)
// and the renderer's optics blur (render/scene_render.h), which may not depend on each other.
#pragma once

#include <vector>

namespace patlab {

// One half of a sampled, truncated, renormalised Gaussian: w[k] = exp(-k^2 / (2 sigma^2)) / sum
// for k = 0..radius, radius = floor(truncate_sigmas * sigma + 0.5), the sum taken over |k| <=
// radius so that w[0] + 2 sum_{k>=1} w[k] = 1 (scipy.ndimage _gaussian_kernel1d). {1} when the
// radius is 0 (also sigma = 0). Requires sigma >= 0 and truncate_sigmas > 0, both finite.
std::vector<double> GaussianHalfKernel(double sigma, double truncate_sigmas);

}  // namespace patlab

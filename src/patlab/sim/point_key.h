// The identity of a data point as a Philox key (core/rng.h StreamKey; docs/architecture.md
// rule 1): a point's random numbers come from (experiment seed, the pattern's content, the noise
// model, sigma, [false-blob rate, codebook, key colours, palette,] trial or frame index), never
// from its position in the grid, the order of the lists or the thread count. So `--sigmas 1`,
// `--sigmas 0.5,1` and the full Fig. 5 sweep give the same row for the Butterfly at sigma = 1 mm,
// byte for byte.
#pragma once

#include <cstdint>

#include "patlab/core/pattern.h"
#include "patlab/core/rng.h"
#include "patlab/detect/detector.h"
#include "patlab/sim/noise.h"

namespace patlab::sim {

// What each kind of point draws from its key: the Philox counter word that names the stream.
inline constexpr uint32_t kKnownStream = 0x6b6e6f77;   // "know": known-correspondence trials
inline constexpr uint32_t kDetectStream = 0x64657463;  // "detc": detect-mode frames

// Folds a pattern's content into `key`: every patch's model position, radius, role and colour, the
// orientation pairs and the key patch, in order; not its name or description (a renamed copy of
// a pattern is the same point).
void AddPattern(const Pattern& pattern, StreamKey* key);
// Folds the four noise-model ratios into `key`. (Sigma enters by its 12-significant-digit text,
// so 3 x 0.1 from a grid and 0.3 from a flag are one point.)
void AddNoise(const NoiseModel& noise, StreamKey* key);

// The key of a known-correspondence point: (seed, "known", pattern, noise, sigma).
uint64_t KnownPointKey(uint64_t seed, const Pattern& pattern, const NoiseModel& noise,
                       double sigma_mm);
// Folds what a detect-mode point's scenes are drawn with, beyond the pattern, into `key`: the
// codebook's content (its ID colours by name, slots and every entry's ID and colouring), the
// key (team) colours by name, and the detector palette by name (a blob's colour label and a
// colour error's draw are palette indices). Not the codebook's file, its pattern name or the
// symmetry tolerance: the same codebook read from a file or generated is the same point.
void AddDetectorPattern(const detect::DetectorPattern& pattern,
                        const std::vector<std::string>& palette, StreamKey* key);

// The key of a detect-mode point: (seed, "detect", pattern, noise, sigma, false-blob rate,
// codebook, key colours, palette). `detector` is the point's DetectorPattern (its pattern is
// folded as `pattern`, by content).
uint64_t DetectPointKey(uint64_t seed, const Pattern& pattern, const NoiseModel& noise,
                        double sigma_mm, double false_blob_rate_per_m2,
                        const detect::DetectorPattern& detector,
                        const std::vector<std::string>& palette);

}  // namespace patlab::sim

// Counter-based random numbers (DESIGN.md rule 1): every random number of a trial is a pure
// function of (experiment seed, stream id, trial index, draw index), computed with Random123's
// Philox4x32-10. Nothing is shared between trials, so results are identical for any thread count
// and any trial can be replayed alone.
//
// Uniforms use 53 bits (two 32-bit words), strictly inside (0, 1). Normals use our own Box-Muller
// transform (never std::normal_distribution, whose output differs between standard libraries).
#pragma once

#include <Random123/philox.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace patlab {

// The four 32-bit words of Philox4x32-10 for counter (a, b, c, d) under a 64-bit key.
inline std::array<uint32_t, 4> PhiloxBlock(uint64_t key, uint32_t a, uint32_t b, uint32_t c,
                                           uint32_t d) {
  r123::Philox4x32 philox;
  const r123::Philox4x32::ctr_type ctr = {{a, b, c, d}};
  const r123::Philox4x32::key_type k = {
      {static_cast<uint32_t>(key), static_cast<uint32_t>(key >> 32)}};
  const auto out = philox(ctr, k);
  return {out[0], out[1], out[2], out[3]};
}

// A uniform double strictly inside (0, 1) from 53 bits of two words.
inline double UniformOpen01(uint32_t hi, uint32_t lo) {
  const uint64_t bits = ((static_cast<uint64_t>(hi) << 32) | lo) >> 11;
  return (static_cast<double>(bits) + 0.5) * 0x1.0p-53;
}

// Box-Muller: two independent standard normals from two uniforms in (0, 1).
// (Box & Muller 1958, Ann. Math. Statist. 29(2).)
inline void BoxMuller(double u1, double u2, double* z0, double* z1) {
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double phi = 2.0 * std::numbers::pi * u2;
  *z0 = r * std::cos(phi);
  *z1 = r * std::sin(phi);
}

// A sequential stream of draws identified by (seed, stream, index): e.g. stream = data point,
// index = trial. Draw k of a stream comes from Philox block k/2, so any draw is reproducible
// without running the others. Cheap to construct; use one per trial or per frame.
class RandomStream {
 public:
  RandomStream(uint64_t seed, uint32_t stream, uint64_t index)
      : seed_(seed), stream_(stream), index_(index) {}

  // A uniform double in (0, 1).
  double Uniform() {
    if (cached_uniforms_ == 0) Refill();
    --cached_uniforms_;
    return uniforms_[cached_uniforms_];
  }
  // A uniform double in (lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // A standard normal.
  double Normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return spare_normal_;
    }
    double z0, z1;
    const double u1 = Uniform();
    const double u2 = Uniform();
    BoxMuller(u1, u2, &z0, &z1);
    spare_normal_ = z1;
    has_spare_normal_ = true;
    return z0;
  }
  // A uniform integer in [0, n), n >= 1: floor(u * n) with a 53-bit u (bias below n / 2^53).
  uint64_t Below(uint64_t n) {
    return static_cast<uint64_t>(Uniform() * static_cast<double>(n)) % n;
  }

 private:
  void Refill() {
    const auto w = PhiloxBlock(seed_, static_cast<uint32_t>(index_),
                               static_cast<uint32_t>(index_ >> 32), stream_, block_++);
    uniforms_[1] = UniformOpen01(w[0], w[1]);
    uniforms_[0] = UniformOpen01(w[2], w[3]);
    cached_uniforms_ = 2;
  }

  uint64_t seed_;
  uint32_t stream_;
  uint64_t index_;
  uint32_t block_ = 0;
  double uniforms_[2] = {0.0, 0.0};
  int cached_uniforms_ = 0;
  bool has_spare_normal_ = false;
  double spare_normal_ = 0.0;
};

}  // namespace patlab

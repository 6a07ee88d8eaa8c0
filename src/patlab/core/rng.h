// Counter-based random numbers (docs/architecture.md rule 1): every random number of a trial is a
// pure function of (key, stream id, trial index, draw index), computed with Random123's
// Philox4x32-10, where the 64-bit key is the StreamKey of the experiment seed and what the data
// point is (never its position in a grid). Nothing is shared between trials, so results are
// identical for any thread count and any trial can be replayed alone.
//
// Uniforms use 52 bits (two 32-bit words) or 32 bits (one word), strictly inside (0, 1). Normals
// use our own Box-Muller transform (never std::normal_distribution, whose output differs between
// standard libraries).
#pragma once

#include <Random123/philox.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string_view>

#include "patlab/core/portable_math.h"

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

// A uniform double strictly inside (0, 1) from the top 52 bits of (hi, lo): the integer
// (hi << 20 | lo >> 12) + 1/2, times 2^-52, so in [2^-53, 1 - 2^-53] (with 53 bits the top value
// would round to 1). Written with 32-bit conversions only (both exact), so that loops over it
// vectorise without AVX-512's 64-bit integer conversion.
inline double UniformOpen01(uint32_t hi, uint32_t lo) {
  return (static_cast<double>(hi) * 0x1.0p20 + static_cast<double>(lo >> 12) + 0.5) * 0x1.0p-52;
}

// A uniform double strictly inside (0, 1) from one 32-bit word: (w + 1/2) 2^-32.
inline double UniformOpen01(uint32_t w) { return (static_cast<double>(w) + 0.5) * 0x1.0p-32; }

// Philox4x32-10 for the counters (c0[k], c1, c2, c3), k < count, under a 64-bit key: the same
// words as PhiloxBlock, as a plain loop over k that the compiler vectorises (Salmon et al. 2011,
// "Parallel random numbers: as easy as 1, 2, 3", the Philox-4x32 round and key schedule).
inline void PhiloxBatch(uint64_t key, const uint32_t* c0, uint32_t c1, uint32_t c2, uint32_t c3,
                        int count, uint32_t* out0, uint32_t* out1, uint32_t* out2, uint32_t* out3) {
  constexpr uint32_t kM0 = 0xD2511F53u, kM1 = 0xCD9E8D57u;  // round multipliers
  constexpr uint32_t kW0 = 0x9E3779B9u, kW1 = 0xBB67AE85u;  // key schedule (Weyl) increments
  const uint32_t key0 = static_cast<uint32_t>(key), key1 = static_cast<uint32_t>(key >> 32);
  for (int k = 0; k < count; ++k) {
    uint32_t x0 = c0[k], x1 = c1, x2 = c2, x3 = c3;
    uint32_t k0 = key0, k1 = key1;
    for (int round = 0; round < 10; ++round) {
      const uint64_t p0 = static_cast<uint64_t>(kM0) * x0;
      const uint64_t p1 = static_cast<uint64_t>(kM1) * x2;
      const uint32_t y0 = static_cast<uint32_t>(p1 >> 32) ^ x1 ^ k0;
      const uint32_t y2 = static_cast<uint32_t>(p0 >> 32) ^ x3 ^ k1;
      x1 = static_cast<uint32_t>(p1);
      x3 = static_cast<uint32_t>(p0);
      x0 = y0;
      x2 = y2;
      k0 += kW0;
      k1 += kW1;
    }
    out0[k] = x0;
    out1[k] = x1;
    out2[k] = x2;
    out3[k] = x3;
  }
}

// Box-Muller: two independent standard normals from two uniforms in (0, 1).
// (Box & Muller 1958, Ann. Math. Statist. 29(2).)
inline void BoxMuller(double u1, double u2, double* z0, double* z1) {
  const double r = std::sqrt(-2.0 * pmath::Log(u1));
  const double phi = 2.0 * std::numbers::pi * u2;
  double sin_phi, cos_phi;
  pmath::SinCos(phi, &sin_phi, &cos_phi);
  *z0 = r * cos_phi;
  *z1 = r * sin_phi;
}

// The 64-bit Philox key of a stream from what the stream *is* (docs/architecture.md rule 1): the
// experiment seed, then every value that identifies the data point (a pattern's geometry, the
// noise model, sigma, ...), folded in order. Two streams share a key only when every value
// agrees, so a point draws the same numbers in any grid, list order or subset it appears in.
// Each step is h <- Fmix64(h ^ Fmix64(w + golden)) with MurmurHash3's 64-bit finaliser (Appleby
// 2011; a bijection with full avalanche), so the key depends on every bit and on the order.
// Doubles enter by their bit pattern, -0 as +0; strings by length, then 8 bytes at a time.
class StreamKey {
 public:
  explicit StreamKey(uint64_t seed) : h_(Fmix64(seed ^ 0x7061746c61622d6bULL)) {}  // "patlab-k"

  StreamKey& Add(uint64_t word) {
    h_ = Fmix64(h_ ^ Fmix64(word + 0x9E3779B97F4A7C15ULL));
    return *this;
  }
  StreamKey& Add(double value) { return Add(std::bit_cast<uint64_t>(value == 0.0 ? 0.0 : value)); }
  StreamKey& Add(std::string_view text) {
    Add(static_cast<uint64_t>(text.size()));
    for (size_t k = 0; k < text.size(); k += 8) {
      uint64_t word = 0;
      for (size_t b = k; b < text.size() && b < k + 8; ++b) {
        word |= static_cast<uint64_t>(static_cast<unsigned char>(text[b])) << (8 * (b - k));
      }
      Add(word);
    }
    return *this;
  }
  uint64_t value() const { return h_; }

  static uint64_t Fmix64(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ULL;
    k ^= k >> 33;
    return k;
  }

 private:
  uint64_t h_;
};

// A sequential stream of draws identified by (key, stream, index): e.g. key = a data point's
// StreamKey, stream = a constant naming what is drawn, index = trial or frame. Draw k of a stream
// comes from Philox block k/2, so any draw is reproducible without running the others. Cheap to
// construct; use one per trial or per frame.
class RandomStream {
 public:
  // `key`: the Philox key, an experiment seed or a StreamKey value.
  RandomStream(uint64_t key, uint32_t stream, uint64_t index)
      : seed_(key), stream_(stream), index_(index) {}

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
  // A uniform integer in [0, n), n >= 1: floor(u * n) with a 52-bit u (bias below n / 2^52).
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

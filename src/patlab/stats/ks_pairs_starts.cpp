// The starts of the paired KS walk's intervals (ks_pairs.cpp): copied from the pairs that differ
// (with AVX-512 eight at a time, the plain loop kept as the fallback), sorted by a key, and checked
// to lie apart.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <utility>

#if defined(__AVX512F__)
#include <immintrin.h>
#define PATLAB_KS_AVX512 1
#endif

#include "patlab/stats/ks_internal.h"

namespace patlab::stats::detail {

// The same values as the plain loop: min_pd(y, x) is y < x ? y : x, as std::min(x, y) (x when
// y is NaN), and NEQ_UQ is x != y (true for NaN).
std::size_t internal::CopyDifferingStarts(const double* x, const double* y, std::size_t c,
                                          double* starts, std::size_t m) {
  std::size_t k = 0;
#ifdef PATLAB_KS_AVX512
  for (; k + 8 <= c; k += 8) {
    const __m512d xv = _mm512_loadu_pd(x + k), yv = _mm512_loadu_pd(y + k);
    const __mmask8 differ = _mm512_cmp_pd_mask(xv, yv, _CMP_NEQ_UQ);
    _mm512_storeu_pd(starts + m,
                     _mm512_maskz_compress_pd(differ, _mm512_maskz_min_pd(0xff, yv, xv)));
    m += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(differ)));
  }
#endif
  for (; k < c; ++k) {
    starts[m] = std::min(x[k], y[k]);
    m += x[k] != y[k] ? 1 : 0;
  }
  return m;
}

namespace internal {
namespace {

// Calls use(i, key(v[i])) for i in [0, m) in order, the keys of a chunk computed first by a loop
// the compiler vectorises (the uses, scattered increments and stores, cannot be).
template <class Key, class Use>
void ForKeys(const double* v, std::size_t m, Key key, Use use) {
  constexpr std::size_t kChunk = 256;
  std::array<uint32_t, kChunk> keys;
  for (std::size_t i0 = 0; i0 < m; i0 += kChunk) {
    const std::size_t c = std::min(kChunk, m - i0);
    for (std::size_t l = 0; l < c; ++l) keys[l] = key(v[i0 + l]);
    for (std::size_t l = 0; l < c; ++l) use(i0 + l, keys[l]);
  }
}

}  // namespace

// Sorts the starts v[0, m) by their keys (scratch w[0, m)): a least-significant-digit radix sort
// of two passes of 11 bits on the key alone, stable, which leaves them in v. Starts with
// different keys are then in order (key(p) < key(q) implies p < q, the key being
// non-decreasing); those with equal keys are in their order in the samples.
void SortStartsByKey(double* v, double* w, std::size_t m, StartKey key) {
  constexpr std::size_t kDigits = std::size_t{1} << kKeyBits;
  std::array<std::array<uint32_t, kDigits>, kKeyPasses> at{};
  ForKeys(v, m, key, [&at](std::size_t, uint32_t k) {
    ++at[0][k & (kDigits - 1)];
    ++at[1][k >> kKeyBits];
  });
  for (auto& digit : at) {
    uint32_t sum = 0;
    for (uint32_t& c : digit) sum += std::exchange(c, sum);
  }
  for (int pass = 0; pass < kKeyPasses; ++pass) {
    const double* from = pass == 0 ? v : w;
    double* to = pass == 0 ? w : v;
    uint32_t* digit = at[static_cast<std::size_t>(pass)].data();
    const int shift = pass * kKeyBits;
    ForKeys(from, m, key, [from, to, digit, shift](std::size_t i, uint32_t k) {
      to[digit[(k >> shift) & (kDigits - 1)]++] = from[i];
    });
  }
}

// True when the starts v[0, m), sorted by key, are each more than 2 * widest above the one
// before (the first above *previous, which becomes the last start). They are compared in the
// order of the keys; where two fail, the run of equal keys around them, whose order is the
// samples', is sorted by value (SortSmall) and compared again: the runs sorted, the order is
// SortAscending's (but for -0.0 and +0.0, which fail either way: 0 - 0 is no gap), and the
// answer is the one of a sort of the values. Fig5's samples: about 2^22 / 25,000 cells a start,
// so a few hundred runs of two among 25,000-39,000 starts, half of them in the wrong order.
bool ApartInKeyOrder(double* v, std::size_t m, StartKey key, double widest, double* previous) {
  const double gap = 2.0 * widest;
  double last = *previous;
  for (std::size_t i = 0; i < m; ++i) {
    if (v[i] - last > gap) {
      last = v[i];
      continue;
    }
    // The run of key(v[i]) and the one of key(v[i - 1]) if different (v[i - 1] may be the last
    // of its run, sorted or not): sorted by value, then compared from the first of them.
    if (i == 0) return false;
    std::size_t begin = i - 1, end = i + 1;
    const uint32_t k_before = key(v[i - 1]), k = key(v[i]);
    while (begin > 0 && key(v[begin - 1]) == k_before) --begin;
    while (end < m && key(v[end]) == k) ++end;
    if (end - begin == 2 && k_before != k) return false;  // two runs of one: already in order
    if (k_before != k) {
      SortSmall(v + begin, i - begin);
      SortSmall(v + i, end - i);
    } else {
      SortSmall(v + begin, end - begin);
    }
    last = begin == 0 ? *previous : v[begin - 1];
    for (std::size_t j = begin; j < end; ++j) {
      if (!(v[j] - last > gap)) return false;
      last = v[j];
    }
    i = end - 1;
  }
  *previous = last;
  return true;
}

}  // namespace internal
}  // namespace patlab::stats::detail

// The planar moments of up to four samples at once (PlanarMomentsOfEach): two passes over the
// columns, each sum a chain of additions in index order, several chains advanced by one vector
// addition, so that every sum has the bits of its scalar loop on any target.
#include <cmath>
#include <cstring>
#include <functional>
#include <span>

#include "patlab/core/error.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/summary_internal.h"

namespace patlab::stats {

using detail::RequireCount;

namespace {

// Pass 2 of the planar moments works on tiles of kTile values: the squared deviations of a tile
// are computed in loops the compiler vectorises and stored in tile buffers (in L1: at most
// 5 samples x 4 columns x 128 values = 20 KiB), and a second loop adds the tile's values to the
// running sums, every sum in index order. A product stored in a buffer and added in another loop
// is rounded before the addition, whatever the compiler's contraction setting. (Pass 1 adds no
// product and works in blocks of 8 indices; see PlanarSums.)
constexpr std::size_t kTile = 128;

// x^2 + y^2 as the runner's former per-estimator loops computed it: GCC contracted x * x + y * y
// into fma(x, x, y * y) on targets with FMA (-march=native here), so the same operation is
// written out, for the same bits under any compiler or contraction setting.
inline double SquaredRadius(double x, double y) {
#ifdef __FMA__
  return std::fma(x, x, y * y);
#else
  const double yy = y * y;
  return x * x + yy;
#endif
}

// The sums of the planar moments are chains: one running sum per column of each sample, advanced
// in index order (that order is what gives the committed bits). Scalar code needs one addition
// per chain and index, and 10 to 20 chains a trial are bound by the adder's throughput. Here the
// chains are the lanes of vectors ("lanes = chains"): lane c of a group holds chain c's sum, a
// block of W indices of W chains is transposed (moves only, exact), and one vector addition then
// advances W chains by one index, in index order. No chain's order of additions changes, so every
// sum has the bits of its scalar loop on any target; the width only decides the speed: 8 doubles
// where the target has AVX-512, 4 with AVX, 2 otherwise (GCC and clang vector extensions; the
// compiler lowers what the target lacks). Chains left over by the widest groups go to narrower
// ones (10 chains with AVX-512: 8 + 2).
using V8 = double __attribute__((vector_size(64)));
using V4 = double __attribute__((vector_size(32)));
using V2 = double __attribute__((vector_size(16)));

#if defined(__AVX512F__)
constexpr int kLaneWidth = 8;
#elif defined(__AVX__)
constexpr int kLaneWidth = 4;
#else
constexpr int kLaneWidth = 2;
#endif

// By reference, not by value: a 64-byte vector passed or returned by value on a target without
// AVX-512 draws GCC's -Wpsabi note.
template <class V>
void LoadVector(V& v, const double* p) {
  std::memcpy(&v, p, sizeof v);
}

// acc[c] += col[c][j + t] for t = 0..7 in that order, c = 0..7: an 8 x 8 transpose in three
// rounds (pairs of doubles, then of 128-bit halves, then of 256-bit halves).
inline void AddTransposed8(V8& acc, const double* const* col, std::size_t j) {
  V8 r[8];
  for (int c = 0; c < 8; ++c) LoadVector(r[c], col[c] + j);
  V8 t[8];  // t[2q] = indices 0, 2, 4, 6 of chains 2q, 2q + 1; t[2q + 1] the odd indices
  for (int q = 0; q < 4; ++q) {
    t[2 * q] = __builtin_shufflevector(r[2 * q], r[2 * q + 1], 0, 8, 2, 10, 4, 12, 6, 14);
    t[2 * q + 1] = __builtin_shufflevector(r[2 * q], r[2 * q + 1], 1, 9, 3, 11, 5, 13, 7, 15);
  }
  V8 u[8];  // u[4h + e]: chains 4h..4h+3 at indices e and e + 4 (e = 0..3)
  for (int h = 0; h < 2; ++h) {
    const V8* th = t + 4 * h;
    u[4 * h + 0] = __builtin_shufflevector(th[0], th[2], 0, 1, 8, 9, 4, 5, 12, 13);
    u[4 * h + 2] = __builtin_shufflevector(th[0], th[2], 2, 3, 10, 11, 6, 7, 14, 15);
    u[4 * h + 1] = __builtin_shufflevector(th[1], th[3], 0, 1, 8, 9, 4, 5, 12, 13);
    u[4 * h + 3] = __builtin_shufflevector(th[1], th[3], 2, 3, 10, 11, 6, 7, 14, 15);
  }
  for (int e = 0; e < 4; ++e)
    acc += __builtin_shufflevector(u[e], u[4 + e], 0, 1, 2, 3, 8, 9, 10, 11);
  for (int e = 0; e < 4; ++e)
    acc += __builtin_shufflevector(u[e], u[4 + e], 4, 5, 6, 7, 12, 13, 14, 15);
}

// acc[c] += col[c][j + t] for t = 0..3 in that order, c = 0..3.
inline void AddTransposed4(V4& acc, const double* const* col, std::size_t j) {
  V4 r0, r1, r2, r3;
  LoadVector(r0, col[0] + j);
  LoadVector(r1, col[1] + j);
  LoadVector(r2, col[2] + j);
  LoadVector(r3, col[3] + j);
  const V4 t0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6);
  const V4 t1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);
  const V4 t2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6);
  const V4 t3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
  acc += __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
  acc += __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
  acc += __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
  acc += __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}

// acc[c] += col[c][j + t] for t = 0, 1 in that order, c = 0, 1.
inline void AddTransposed2(V2& acc, const double* const* col, std::size_t j) {
  V2 r0, r1;
  LoadVector(r0, col[0] + j);
  LoadVector(r1, col[1] + j);
  acc += __builtin_shufflevector(r0, r1, 0, 2);
  acc += __builtin_shufflevector(r0, r1, 1, 3);
}

// C chains in groups of 8 (AVX-512), then 4 (AVX), then 2, then one scalar.
template <int C>
class LaneSums {
 public:
  static constexpr std::size_t kBlock = 8;  // indices advanced by Add

  // Every chain c += col[c][j], ..., col[c][j + 7], in that order.
  void Add(const double* const* col, std::size_t j) {
    for (int g = 0; g < kGroups8; ++g) AddTransposed8(a8_[g], col + 8 * g, j);
    for (int g = 0; g < kGroups4; ++g) {
      for (std::size_t t = 0; t < kBlock; t += 4)
        AddTransposed4(a4_[g], col + kFirst4 + 4 * g, j + t);
    }
    for (int g = 0; g < kGroups2; ++g) {
      for (std::size_t t = 0; t < kBlock; t += 2)
        AddTransposed2(a2_[g], col + kFirst2 + 2 * g, j + t);
    }
    for (int c = kFirst1; c < C; ++c) {
      for (std::size_t t = 0; t < kBlock; ++t) a1_[c - kFirst1] += col[c][j + t];
    }
  }
  // Every chain c += col[c][j] (the tail of a tile).
  void AddOne(const double* const* col, std::size_t j) {
    for (int c = 0; c < kFirst4; ++c) a8_[c / 8][c % 8] += col[c][j];
    for (int c = kFirst4; c < kFirst2; ++c) a4_[(c - kFirst4) / 4][(c - kFirst4) % 4] += col[c][j];
    for (int c = kFirst2; c < kFirst1; ++c) a2_[(c - kFirst2) / 2][(c - kFirst2) % 2] += col[c][j];
    for (int c = kFirst1; c < C; ++c) a1_[c - kFirst1] += col[c][j];
  }
  double Sum(int c) const {
    if (c < kFirst4) return a8_[c / 8][c % 8];
    if (c < kFirst2) return a4_[(c - kFirst4) / 4][(c - kFirst4) % 4];
    if (c < kFirst1) return a2_[(c - kFirst2) / 2][(c - kFirst2) % 2];
    return a1_[c - kFirst1];
  }

 private:
  static constexpr int kGroups8 = kLaneWidth >= 8 ? C / 8 : 0;
  static constexpr int kFirst4 = 8 * kGroups8;
  static constexpr int kGroups4 = kLaneWidth >= 4 ? (C - kFirst4) / 4 : 0;
  static constexpr int kFirst2 = kFirst4 + 4 * kGroups4;
  static constexpr int kGroups2 = (C - kFirst2) / 2;
  static constexpr int kFirst1 = kFirst2 + 2 * kGroups2;
  V8 a8_[std::max(kGroups8, 1)] = {};
  V4 a4_[std::max(kGroups4, 1)] = {};
  V2 a2_[std::max(kGroups2, 1)] = {};
  double a1_[std::max(C - kFirst1, 1)] = {};
};

// Advances `sums` by the first m indices of the columns col (a tile), in index order.
template <int C>
void AddTile(LaneSums<C>& sums, const double* const* col, std::size_t m) {
  constexpr std::size_t kBlock = LaneSums<C>::kBlock;
  std::size_t j = 0;
  for (; j + kBlock <= m; j += kBlock) sums.Add(col, j);
  for (; j < m; ++j) sums.AddOne(col, j);
}

struct PlanarColumns {
  const double* x[kMaxPlanarSamples];
  const double* y[kMaxPlanarSamples];
  const double* theta[kMaxPlanarSamples];
};

// Pass 1 of K samples: the sums of x, y, theta, x^2 + y^2 and r, in index order. Chains: 4k + 0..3
// are sample k's x, y, theta and x^2 + y^2, chain 4K + k its r. No tile: each block of 8 indices
// computes its squares and roots into 8-value buffers (a loop the compiler vectorises) and adds
// them at once, so the loads of the next block overlap the additions of this one (the columns are
// read from memory only here and in pass 2). No product is added here: x^2 + y^2 is
// SquaredRadius's explicit rule.
template <int K>
void PlanarSums(const PlanarColumns& c, std::size_t n, double (&sum_out)[5][K]) {
  using Sums = LaneSums<5 * K>;
  constexpr std::size_t kBlock = Sums::kBlock;
  Sums sums;
  alignas(64) double sq[K][kBlock];
  alignas(64) double r[K][kBlock];
  const double* col[5 * K];
  auto block = [&](std::size_t i0, std::size_t m) {
    for (int k = 0; k < K; ++k) {
      const double* x = c.x[k] + i0;
      const double* y = c.y[k] + i0;
      for (std::size_t j = 0; j < m; ++j) sq[k][j] = SquaredRadius(x[j], y[j]);
      for (std::size_t j = 0; j < m; ++j) r[k][j] = std::sqrt(sq[k][j]);
      col[4 * k + 0] = x;
      col[4 * k + 1] = y;
      col[4 * k + 2] = c.theta[k] + i0;
      col[4 * k + 3] = sq[k];
      col[4 * K + k] = r[k];
    }
  };
  std::size_t i0 = 0;
  for (; i0 + kBlock <= n; i0 += kBlock) {
    block(i0, kBlock);
    sums.Add(col, 0);
  }
  block(i0, n - i0);
  for (std::size_t j = 0; j < n - i0; ++j) sums.AddOne(col, j);
  for (int k = 0; k < K; ++k) {
    for (int q = 0; q < 4; ++q) sum_out[q][k] = sums.Sum(4 * k + q);
    sum_out[4][k] = sums.Sum(4 * K + k);
  }
}

// Pass 2 of K samples: the sums of squared deviations from mean[0..3] (x, y, theta, r). Chain
// 4k + q is sample k's column q. Each tile's radial errors are kept in a tile buffer and shown to
// `visit` (a no-op for PlanarMomentsOfEach without a visitor) once the tile has been read.
template <int K, class Visit>
void PlanarDeviations(const PlanarColumns& c, std::size_t n, const double (&mean)[4][K],
                      double (&m2_out)[4][K], Visit visit) {
  LaneSums<4 * K> sums;
  alignas(64) double d2[K][4][kTile];
  alignas(64) double radial[K][kTile];
  for (std::size_t i0 = 0; i0 < n; i0 += kTile) {
    const std::size_t m = std::min(kTile, n - i0);
    const double* col[4 * K];
    for (int k = 0; k < K; ++k) {
      const double* x = c.x[k] + i0;
      const double* y = c.y[k] + i0;
      const double* t = c.theta[k] + i0;
      for (std::size_t j = 0; j < m; ++j) {
        const double dx = x[j] - mean[0][k], dy = y[j] - mean[1][k], dt = t[j] - mean[2][k];
        d2[k][0][j] = dx * dx;
        d2[k][1][j] = dy * dy;
        d2[k][2][j] = dt * dt;
        radial[k][j] = std::sqrt(SquaredRadius(x[j], y[j]));
        const double dr = radial[k][j] - mean[3][k];
        d2[k][3][j] = dr * dr;
      }
      for (int q = 0; q < 4; ++q) col[4 * k + q] = d2[k][q];
    }
    visit(i0, m, radial);
    AddTile(sums, col, m);
  }
  for (int k = 0; k < K; ++k) {
    for (int q = 0; q < 4; ++q) m2_out[q][k] = sums.Sum(4 * k + q);
  }
}

template <int K, class Visit>
void PlanarMomentsInterleaved(const PlanarSample* samples, std::size_t n, PlanarMoments* out,
                              Visit visit) {
  PlanarColumns c{};
  for (int k = 0; k < K; ++k) {
    c.x[k] = samples[k].x.data();
    c.y[k] = samples[k].y.data();
    c.theta[k] = samples[k].theta.data();
  }
  double sum[5][K];
  PlanarSums<K>(c, n, sum);
  // A non-finite value makes its column's sum non-finite, and only then are the columns searched
  // for it (a finite sample can also overflow its sum; then the search finds nothing and the
  // moments are what the arithmetic gives).
  for (int k = 0; k < K; ++k) {
    if (!std::isfinite(sum[0][k]) || !std::isfinite(sum[1][k]) || !std::isfinite(sum[2][k])) {
      for (int j = 0; j < K; ++j) {
        detail::RequireFinite(samples[j].x, "sample");
        detail::RequireFinite(samples[j].y, "sample");
        detail::RequireFinite(samples[j].theta, "sample");
      }
      break;
    }
  }
  const double count = static_cast<double>(n);
  double mean[4][K];
  for (int k = 0; k < K; ++k) {
    for (int q = 0; q < 3; ++q) mean[q][k] = sum[q][k] / count;
    mean[3][k] = sum[4][k] / count;
  }
  double m2[4][K];
  PlanarDeviations<K>(c, n, mean, m2, visit);
  const auto size = static_cast<std::int64_t>(n);
  for (int k = 0; k < K; ++k) {
    out[k].x = Moments{size, mean[0][k], m2[0][k]};
    out[k].y = Moments{size, mean[1][k], m2[1][k]};
    out[k].theta = Moments{size, mean[2][k], m2[2][k]};
    out[k].radial = Moments{size, mean[3][k], m2[3][k]};
    out[k].sum_sq = sum[3][k];
  }
}

template <class Visit>
void PlanarMomentsWith(std::span<const PlanarSample> samples, std::span<PlanarMoments> out,
                       Visit visit) {
  PATLAB_CHECK(samples.size() <= kMaxPlanarSamples && out.size() == samples.size());
  if (samples.empty()) return;
  const std::size_t n = samples[0].x.size();
  for (const PlanarSample& s : samples) {
    PATLAB_CHECK(s.x.size() == n && s.y.size() == n && s.theta.size() == n);
  }
  RequireCount(samples[0].x, 1, "the moments");
  switch (samples.size()) {
    case 1:
      PlanarMomentsInterleaved<1>(samples.data(), n, out.data(), visit);
      break;
    case 2:
      PlanarMomentsInterleaved<2>(samples.data(), n, out.data(), visit);
      break;
    case 3:
      PlanarMomentsInterleaved<3>(samples.data(), n, out.data(), visit);
      break;
    case 4:
      PlanarMomentsInterleaved<4>(samples.data(), n, out.data(), visit);
      break;
    default:
      PlanarMomentsInterleaved<5>(samples.data(), n, out.data(), visit);
      break;
  }
}

}  // namespace

void PlanarMomentsOfEach(std::span<const PlanarSample> samples, std::span<PlanarMoments> out) {
  PlanarMomentsWith(samples, out, [](std::size_t, std::size_t, const auto&) {});
}

void PlanarMomentsOfEach(std::span<const PlanarSample> samples, std::span<PlanarMoments> out,
                         const std::function<void(const PlanarTile&)>& visit) {
  PlanarMomentsWith(samples, out,
                    [&visit](std::size_t first, std::size_t count, const auto& radial) {
                      PlanarTile tile;
                      tile.first = first;
                      tile.count = count;
                      for (std::size_t k = 0; k < std::size(radial); ++k)
                        tile.radial[k] = radial[k];
                      visit(tile);
                    });
}

}  // namespace patlab::stats

// EstimateMany: blocks of kBlock trials gathered from the strided array into columns, then each
// estimator's stages as plain loops over the block (vectorised), then the poses written as rows.
// Every expression repeats estimators.cpp's for one trial, in its order: the mean as
// ((0 + v_0) + v_1) + ... divided by n, the pairs' rotated displacements summed from 0, Atan2,
// SinCos of the unwrapped angle, the origin, the angle wrapped (WrapAngleNear equals WrapAngle
// on Atan2's range). Compiled with -fno-trapping-math (CMakeLists.txt), as sim/batch.cpp, so that
// the selects of portable_math.h become vector blends; the option changes no value.
#include "patlab/estimate/estimators_many.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"

namespace patlab::estimate {

namespace {

constexpr int kBlock = 256;

struct Columns {
  std::array<std::array<double, kBlock>, kMaxPatches> x, y;  // patch i, trial k
  std::array<double, kBlock> mean_x, mean_y, sum_a, sum_b, theta, s, c;
};

double Load(const unsigned char* at) {
  double v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

// Patch by patch, so that the columns are written in order (the block's trials, 16 KB for a
// (N, 4, 2) array, stay in the first-level cache after the first patch has read them).
void Gather(const Model& model, const PatchArray& in, int64_t first, int m, Columns& w) {
  const unsigned char* block = in.data + first * in.trial_stride;
  for (int i = 0; i < model.num_patches; ++i) {
    const unsigned char* patch = block + i * in.patch_stride;
    double* x = w.x[i].data();
    double* y = w.y[i].data();
    for (int k = 0; k < m; ++k) {
      x[k] = Load(patch + k * in.trial_stride);
      y[k] = Load(patch + k * in.trial_stride + in.axis_stride);
    }
  }
}

// A C-ordered (trials, N, 2) array of aligned doubles (numpy's default): each trial's 2N numbers
// one after the other, gathered with N known to the compiler, which then loads whole trials
// and permutes them into the columns.
template <int N>
void GatherPacked(const double* block, int m, Columns& w) {
  for (int k = 0; k < m; ++k) {
    const double* trial = block + 2 * N * k;
    for (int i = 0; i < N; ++i) {
      w.x[i][k] = trial[2 * i];
      w.y[i][k] = trial[2 * i + 1];
    }
  }
}

template <int... N>
bool GatherPackedAny(int n, const double* block, int m, Columns& w,
                     std::integer_sequence<int, N...>) {
  return ((n == N ? (GatherPacked<N>(block, m, w), true) : false) || ...);
}

void GatherAny(const Model& model, const PatchArray& in, int64_t first, int m, Columns& w) {
  const std::ptrdiff_t d = sizeof(double);
  const int n = model.num_patches;
  const bool packed = in.axis_stride == d && in.patch_stride == 2 * d &&
                      in.trial_stride == 2 * n * d &&
                      reinterpret_cast<uintptr_t>(in.data) % alignof(double) == 0;
  if (packed && GatherPackedAny(n, reinterpret_cast<const double*>(in.data) + 2 * n * first, m, w,
                                std::integer_sequence<int, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12>{})) {
    return;
  }
  Gather(model, in, first, m, w);
}

// estimators.cpp's Mean: the sum from zero, divided by n.
void Mean(const Model& model, int m, Columns& w) {
  for (int k = 0; k < m; ++k) w.mean_x[k] = w.mean_y[k] = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    for (int k = 0; k < m; ++k) {
      w.mean_x[k] += w.x[i][k];
      w.mean_y[k] += w.y[i][k];
    }
  }
  const double n = static_cast<double>(model.num_patches);
  if ((model.num_patches & (model.num_patches - 1)) == 0) {
    // n a power of two: x / n and x * (1 / n) are the same correctly rounded number (1 / n is
    // exact), and a multiplication costs a fraction of a division.
    const double inv_n = 1.0 / n;
    for (int k = 0; k < m; ++k) {
      w.mean_x[k] *= inv_n;
      w.mean_y[k] *= inv_n;
    }
    return;
  }
  for (int k = 0; k < m; ++k) {
    w.mean_x[k] /= n;
    w.mean_y[k] /= n;
  }
}

// estimators.cpp's FastAngle: the pairs' displacements rotated back, summed, atan2.
void FastAngle(const Model& model, int m, Columns& w) {
  for (int k = 0; k < m; ++k) w.sum_a[k] = w.sum_b[k] = 0.0;
  for (int j = 0; j < model.num_pairs; ++j) {
    const double* fx = w.x[model.pair_from[j]].data();
    const double* fy = w.y[model.pair_from[j]].data();
    const double* tx = w.x[model.pair_to[j]].data();
    const double* ty = w.y[model.pair_to[j]].data();
    const double c = model.pair_cos[j], s = model.pair_sin[j];
    for (int k = 0; k < m; ++k) {
      const double dx = tx[k] - fx[k], dy = ty[k] - fy[k];
      w.sum_a[k] += c * dx + s * dy;
      w.sum_b[k] += -s * dx + c * dy;
    }
  }
  for (int k = 0; k < m; ++k) w.theta[k] = pmath::Atan2(w.sum_b[k], w.sum_a[k]);
}

// estimators.cpp's LeastSquares angle: centred model against centred data.
void LeastSquaresAngle(const Model& model, int m, Columns& w) {
  for (int k = 0; k < m; ++k) w.sum_a[k] = w.sum_b[k] = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const double qx = model.model_mm[i].x() - model.centroid_mm.x();
    const double qy = model.model_mm[i].y() - model.centroid_mm.y();
    for (int k = 0; k < m; ++k) {
      const double wx = w.x[i][k] - w.mean_x[k], wy = w.y[i][k] - w.mean_y[k];
      w.sum_a[k] += qx * wx + qy * wy;
      w.sum_b[k] += qx * wy - qy * wx;
    }
  }
  for (int k = 0; k < m; ++k) w.theta[k] = pmath::Atan2(w.sum_b[k], w.sum_a[k]);
}

// estimators.cpp's OriginFrom: the origin whose pose maps `ref` to the anchor at w.theta.
void Origin(const double* anchor_x, const double* anchor_y, const Vec2& ref, int m, Columns& w,
            double* poses) {
  for (int k = 0; k < m; ++k) pmath::SinCos(w.theta[k], &w.s[k], &w.c[k]);
  const double rx = ref.x(), ry = ref.y();
  for (int k = 0; k < m; ++k) {
    poses[3 * k] = anchor_x[k] - (w.c[k] * rx - w.s[k] * ry);
    poses[3 * k + 1] = anchor_y[k] - (w.s[k] * rx + w.c[k] * ry);
    poses[3 * k + 2] = pmath::WrapAngleNear(w.theta[k]);
  }
}

inline void EstimateBlock(const Model& model, Estimator method, const PatchArray& in, int64_t first,
                          int m, double* poses) {
  thread_local Columns w;
  GatherAny(model, in, first, m, w);
  switch (method) {
    case Estimator::kFast:
      Mean(model, m, w);
      FastAngle(model, m, w);
      return Origin(w.mean_x.data(), w.mean_y.data(), model.centroid_mm, m, w, poses);
    case Estimator::kKey:
      FastAngle(model, m, w);
      return Origin(w.x[model.key_index].data(), w.y[model.key_index].data(),
                    model.model_mm[model.key_index], m, w, poses);
    case Estimator::kLsq:
      Mean(model, m, w);
      LeastSquaresAngle(model, m, w);
      return Origin(w.mean_x.data(), w.mean_y.data(), model.centroid_mm, m, w, poses);
    default:
      PATLAB_CHECK(false && "EstimateMany runs fast, key and lsq");
  }
}

inline void EstimateBlocks(const Model& model, Estimator method, const PatchArray& in,
                           int64_t first, int64_t count, double* poses) {
  for (int64_t done = 0; done < count; done += kBlock) {
    const int m = static_cast<int>(std::min<int64_t>(kBlock, count - done));
    EstimateBlock(model, method, in, first + done, m, poses + 3 * done);
  }
}

// One version per instruction set, every stage inlined into it (flatten), as sim/batch.cpp's
// kernel: wider vectors run more trials at once and give the same bits.
__attribute__((flatten)) void Baseline(const Model& model, Estimator method, const PatchArray& in,
                                       int64_t first, int64_t count, double* poses) {
  EstimateBlocks(model, method, in, first, count, poses);
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define PATLAB_MANY_ISA_VERSIONS 1
__attribute__((flatten, target("arch=x86-64-v3"))) void Avx2(const Model& model, Estimator method,
                                                             const PatchArray& in, int64_t first,
                                                             int64_t count, double* poses) {
  EstimateBlocks(model, method, in, first, count, poses);
}

__attribute__((flatten, target("arch=x86-64-v4"))) void Avx512(const Model& model, Estimator method,
                                                               const PatchArray& in, int64_t first,
                                                               int64_t count, double* poses) {
  EstimateBlocks(model, method, in, first, count, poses);
}
#else
#define PATLAB_MANY_ISA_VERSIONS 0
#endif

}  // namespace

bool HasManyVersion(Estimator method) {
  return method == Estimator::kFast || method == Estimator::kKey || method == Estimator::kLsq;
}

namespace {

ManyIsa WidestManyIsa() {
#if PATLAB_MANY_ISA_VERSIONS
  static const ManyIsa widest = __builtin_cpu_supports("x86-64-v4")   ? ManyIsa::kAvx512
                                : __builtin_cpu_supports("x86-64-v3") ? ManyIsa::kAvx2
                                                                      : ManyIsa::kBaseline;
  return widest;
#else
  return ManyIsa::kBaseline;
#endif
}

}  // namespace

std::vector<ManyIsa> SupportedManyIsas() {
  std::vector<ManyIsa> isas;
  for (ManyIsa isa : {ManyIsa::kBaseline, ManyIsa::kAvx2, ManyIsa::kAvx512}) {
    if (isa <= WidestManyIsa()) isas.push_back(isa);
  }
  return isas;
}

void EstimateManyWith(ManyIsa isa, const Model& model, Estimator method, const PatchArray& patches,
                      int64_t first, int64_t count, double* poses) {
  PATLAB_CHECK(HasManyVersion(method));
  PATLAB_CHECK(isa <= WidestManyIsa());
  switch (isa) {
#if PATLAB_MANY_ISA_VERSIONS
    case ManyIsa::kAvx512:
      return Avx512(model, method, patches, first, count, poses);
    case ManyIsa::kAvx2:
      return Avx2(model, method, patches, first, count, poses);
#endif
    default:
      return Baseline(model, method, patches, first, count, poses);
  }
}

void EstimateMany(const Model& model, Estimator method, const PatchArray& patches, int64_t first,
                  int64_t count, double* poses) {
  EstimateManyWith(WidestManyIsa(), model, method, patches, first, count, poses);
}

}  // namespace patlab::estimate

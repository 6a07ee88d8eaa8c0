// The closed-form estimators of estimators.h (fast, key patch, least squares) over many trials at
// once, read in place from a strided array of observed patches: what a notebook hands over as a
// numpy (trials, patches, 2) array, or a C++ caller as its own buffer. Pose k is the estimator's
// pose of trial k alone, bit for bit (estimate::Fast, KeyPatch, LeastSquares): the same
// operations in the same order, each stage a loop over a block of trials that the compiler
// vectorises, with patlab's own transcendentals (core/portable_math.h) and no fused multiply-add,
// at the widest vector width the CPU has (docs/architecture.md, "Same bytes on every machine").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "patlab/estimate/estimators.h"

namespace patlab::estimate {

// Observed patch positions of many trials: coordinate a (0: x, 1: y, in mm) of patch i (the
// pattern's order) of trial t is the double at data + t * trial_stride + i * patch_stride +
// a * axis_stride, strides in bytes, any sign (numpy's strides), alignment not required.
struct PatchArray {
  const unsigned char* data = nullptr;
  std::ptrdiff_t trial_stride = 0;
  std::ptrdiff_t patch_stride = 0;
  std::ptrdiff_t axis_stride = 0;
};

// True for the estimators EstimateMany runs: kFast, kKey and kLsq (closed forms, no iteration).
bool HasManyVersion(Estimator method);

// Poses of trials [first, first + count) of `patches` by `method` (HasManyVersion), written as
// rows (x mm, y mm, theta rad) into poses[3 * k .. 3 * k + 2] for trial first + k. Does not
// allocate. The trials may be split among threads in any way: each pose depends on its trial
// alone.
void EstimateMany(const Model& model, Estimator method, const PatchArray& patches, int64_t first,
                  int64_t count, double* poses);

// The instruction sets EstimateMany has a version for. EstimateMany runs the widest this CPU has;
// EstimateManyWith runs the one named (one of SupportedManyIsas), so that a test can check that
// every version gives the same bits (docs/architecture.md, rule 13).
enum class ManyIsa { kBaseline, kAvx2, kAvx512 };
std::vector<ManyIsa> SupportedManyIsas();
void EstimateManyWith(ManyIsa isa, const Model& model, Estimator method, const PatchArray& patches,
                      int64_t first, int64_t count, double* poses);

}  // namespace patlab::estimate

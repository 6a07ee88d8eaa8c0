// Detect's optional explain records (detector.h KeyExplanation): the outcome of stages 2-6 for
// one key and the nearest rotation its full fits tried. Runs only when Detect is asked to explain.
#include <algorithm>
#include <cmath>
#include <limits>

#include "patlab/detect/detector_internal.h"

namespace patlab::detect {

using internal::PatternRuntime;

// The outcome of stages 2-6 for one key; kDetected may still become kConflict in stage 7.
void Detector::Impl::ExplainKey(int p, int key, const Vec2& key_mm, const Neighbours& nb,
                                const DetectStats& before, bool found) {
  const PatternRuntime& rt = runtimes[p];
  KeyExplanation e;
  e.pattern = p;
  e.key_blob = key;
  e.neighbours = nb.n;
  e.needed = rt.mk;
  e.rotations = stats.correspondences - before.correspondences;
  e.geometry_passed = stats.geometry_passed - before.geometry_passed;
  e.best_e_mm2 = key_best_e;
  e.tolerance_mm2 = rt.e_max_full;
  e.nearest_blob.fill(-1);
  ExplainNearestRotation(p, key_mm, nb, &e);
  const bool enough = nb.n >= rt.mk || (rt.can_fit_missing && nb.n >= rt.mk - 1);
  if (found) {
    e.outcome = KeyOutcome::kDetected;
    candidates.back().explain = static_cast<int>(explain->size());
  } else if (!enough) {
    e.outcome = KeyOutcome::kFewNeighbours;
  } else if (e.geometry_passed == 0) {
    e.outcome = KeyOutcome::kGeometry;
  } else {
    e.outcome = KeyOutcome::kColours;
  }
  explain->push_back(e);
}

// The rotation of key_best_pick with the smallest E, recomputed as stage 4 computes it
// (2-D Procrustes, Umeyama 1991: E = sum|q|^2 + sum|w|^2 - 2 sqrt(A^2 + B^2)).
void Detector::Impl::ExplainNearestRotation(int p, const Vec2& key_mm, const Neighbours& nb,
                                            KeyExplanation* e) const {
  const PatternRuntime& rt = runtimes[p];
  const int r = key_best_r;
  if (r == 0) return;
  e->nearest_blob[static_cast<size_t>(rt.key_index)] = e->key_blob;
  Vec2 centroid = key_mm;
  for (int i = 0; i < r; ++i) centroid += nb.position_mm[key_best_pick[i]];
  centroid /= (r + 1);
  const Vec2 wk = key_mm - centroid;
  double sw = wk.squaredNorm();
  for (int i = 0; i < r; ++i) sw += (nb.position_mm[key_best_pick[i]] - centroid).squaredNorm();
  double best = std::numeric_limits<double>::infinity();
  for (int shift = 0; shift < r; ++shift) {
    const Vec2& qk = rt.key_centred[0];
    double a = qk.dot(wk), b = qk.x() * wk.y() - qk.y() * wk.x();
    for (int i = 0; i < r; ++i) {
      const Vec2& q = rt.ring_centred[0][shift + i];
      const Vec2 w = nb.position_mm[key_best_pick[i]] - centroid;
      a += q.dot(w);
      b += q.x() * w.y() - q.y() * w.x();
    }
    const double fit = std::max(0.0, rt.sq[0] + sw - 2.0 * std::sqrt(a * a + b * b));
    if (fit < best) {
      best = fit;
      e->nearest_rotation = shift;
    }
  }
  for (int i = 0; i < r; ++i) {
    const int patch = rt.circ_patch[rt.ring[0][e->nearest_rotation + i]];
    e->nearest_blob[static_cast<size_t>(patch)] = nb.blob[key_best_pick[i]];
  }
}

}  // namespace patlab::detect

#include "patlab/core/pattern.h"

namespace patlab {

Vec2 Pattern::Centroid() const {
  Vec2 sum = Vec2::Zero();
  for (const Patch& p : patches) sum += p.position_mm;
  return sum / static_cast<double>(patches.size());
}

double Pattern::Spread() const {
  const Vec2 c = Centroid();
  double s = 0.0;
  for (const Patch& p : patches) s += (p.position_mm - c).squaredNorm();
  return s;
}

std::vector<OrientationPair> DefaultOrientationPairs(const std::vector<Patch>& patches,
                                                     int key_index) {
  std::vector<int> others;
  for (int i = 0; i < static_cast<int>(patches.size()); ++i) {
    if (i != key_index) others.push_back(i);
  }
  std::vector<OrientationPair> pairs;
  if (others.size() == 1) {
    pairs.push_back({key_index, others[0]});
    return pairs;
  }
  for (size_t a = 0; a < others.size(); ++a) {
    for (size_t b = a + 1; b < others.size(); ++b) pairs.push_back({others[a], others[b]});
  }
  return pairs;
}

}  // namespace patlab

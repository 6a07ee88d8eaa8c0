// ID capacity of layouts whose patches differ in size: the rule (CountIds over the effective
// group of FindSymmetry) against a brute force that knows nothing of circular orders, shifts or
// Burnside: it finds the layout's rotations about the key by matching patches (position within
// 1e-6 mm, same radius, same role and fixed colour), enumerates every colouring of the ID slots
// and counts the orbits of those that no rotation but the identity maps onto themselves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"

namespace patlab::detect {
namespace {

// A key at the origin and m patches at angles 2 pi j / m on a circle of 60 mm.
Pattern RegularLayout(const std::vector<double>& radii, const std::vector<std::string>& roles) {
  Pattern p;
  p.name = "regular";
  Patch key;
  key.role = PatchRole::kKey;
  key.radius_mm = 25.0;
  p.patches.push_back(key);
  const auto m = static_cast<double>(radii.size());
  for (size_t j = 0; j < radii.size(); ++j) {
    Patch patch;
    const double a = 2.0 * std::numbers::pi * static_cast<double>(j) / m + 0.1;
    patch.position_mm = Vec2(60.0 * std::cos(a), 60.0 * std::sin(a));
    patch.radius_mm = radii[j];
    patch.role = roles[j].empty() ? PatchRole::kId : PatchRole::kFixed;
    patch.colour = roles[j];
    p.patches.push_back(patch);
  }
  p.key_index = 0;
  return p;
}

// For each rotation about the key that maps the layout onto itself (patch by patch: position,
// radius, role, fixed colour), the permutation of ID slots it induces.
std::vector<std::vector<int>> BruteForceRotations(const Pattern& p) {
  std::vector<int> slots;
  for (int i = 0; i < p.size(); ++i) {
    if (p.patches[i].role == PatchRole::kId) slots.push_back(i);
  }
  const int first = p.key_index == 0 ? 1 : 0;
  const Vec2 a = p.patches[first].position_mm;
  std::vector<std::vector<int>> perms;
  for (int target = 0; target < p.size(); ++target) {
    if (target == p.key_index) continue;
    const Vec2 b = p.patches[target].position_mm;
    const double angle = std::atan2(b.y(), b.x()) - std::atan2(a.y(), a.x());
    const double c = std::cos(angle), s = std::sin(angle);
    std::vector<int> image(p.size(), -1);
    bool ok = true;
    for (int i = 0; i < p.size() && ok; ++i) {
      const Vec2 q = p.patches[i].position_mm;
      const Vec2 r(c * q.x() - s * q.y(), s * q.x() + c * q.y());
      for (int k = 0; k < p.size(); ++k) {
        const Patch& from = p.patches[i];
        const Patch& to = p.patches[k];
        if ((to.position_mm - r).norm() < 1e-6 && to.radius_mm == from.radius_mm &&
            to.role == from.role && to.colour == from.colour) {
          image[i] = k;
        }
      }
      ok = image[i] >= 0;
    }
    if (!ok) continue;
    std::vector<int> perm;
    for (int slot : slots) {
      for (size_t k = 0; k < slots.size(); ++k) {
        if (slots[k] == image[slot]) perm.push_back(static_cast<int>(k));
      }
    }
    perms.push_back(perm);
  }
  return perms;
}

// Orbits of colourings (n colours) with a trivial stabiliser under `perms`.
uint64_t BruteForceIds(const std::vector<std::vector<int>>& perms, size_t slots, int n) {
  std::set<std::vector<int>> orbits;
  std::vector<int> colour(slots, 0);
  const auto total = static_cast<uint64_t>(std::pow(n, static_cast<double>(slots)));
  for (uint64_t code = 0; code < total; ++code) {
    uint64_t rest = code;
    for (size_t k = 0; k < slots; ++k, rest /= static_cast<uint64_t>(n)) {
      colour[k] = static_cast<int>(rest % static_cast<uint64_t>(n));
    }
    std::set<std::vector<int>> images;
    for (const std::vector<int>& perm : perms) {
      std::vector<int> moved(slots);
      for (size_t k = 0; k < slots; ++k) moved[static_cast<size_t>(perm[k])] = colour[k];
      images.insert(moved);
    }
    if (images.size() == perms.size()) orbits.insert(*images.begin());
  }
  return orbits.size();
}

// A hexagon of six ID dots, radii 15 and 25 mm alternating: its rotations are the thirds of a
// turn (Z3, two 3-cycles of slots), 20 IDs with 2 colours ((2^6 - 2^2) / 3); counted under the
// sixths of a turn, as if size did not tell dots apart, it has (64 - 8 - 4 + 2) / 6 = 9.
TEST(IdCapacity, TwoRadiusHexagonCountsUnderTheSizePreservingRotations) {
  const Pattern hexagon = RegularLayout({15, 25, 15, 25, 15, 25}, {"", "", "", "", "", ""});
  const Symmetry symmetry = FindSymmetry(hexagon, 10.0);
  EXPECT_EQ(symmetry.group_order(), 6);
  EXPECT_EQ(symmetry.effective_order(), 3);
  EXPECT_EQ(CountIds(hexagon, symmetry, 2), 20u);
  EXPECT_EQ(BruteForceIds(BruteForceRotations(hexagon), 6, 2), 20u);
  // Sizes within the tolerance (diameters 30 and 40 mm, 10 mm apart) are one size: Z6, 9 IDs.
  const Pattern close = RegularLayout({15, 20, 15, 20, 15, 20}, {"", "", "", "", "", ""});
  EXPECT_EQ(CountIds(close, FindSymmetry(close, 10.0), 2), 9u);
}

// 40 random regular layouts (3-8 patches, radii 15 or 25 mm, a few fixed white or black dots),
// 2 and 3 colours: the rule and the brute force agree on every one.
TEST(IdCapacity, RuleAgreesWithBruteForceOnRandomLayoutsWithMixedRadii) {
  std::mt19937 rng(2003);
  int nontrivial = 0;
  for (int layout = 0; layout < 40; ++layout) {
    const auto m = 3 + static_cast<int>(rng() % 6);
    const int period = 1 + static_cast<int>(rng() % static_cast<unsigned>(m));
    // A motif of `period` patches repeated round the circle (so that some rotations survive
    // when period divides m), broken at one patch in every fourth layout.
    std::vector<double> motif_radius;
    std::vector<std::string> motif_role;
    for (int j = 0; j < period; ++j) {
      motif_radius.push_back(rng() % 2 == 0 ? 15.0 : 25.0);
      const unsigned role = rng() % 6;
      motif_role.emplace_back(role == 0 ? "white" : role == 1 ? "black" : "");
    }
    std::vector<double> radii;
    std::vector<std::string> roles;
    for (int j = 0; j < m; ++j) {
      radii.push_back(motif_radius[static_cast<size_t>(j % period)]);
      roles.push_back(motif_role[static_cast<size_t>(j % period)]);
    }
    if (layout % 4 == 3) radii[0] = radii[0] == 15.0 ? 25.0 : 15.0;
    const Pattern p = RegularLayout(radii, roles);
    const Symmetry symmetry = FindSymmetry(p, 10.0);
    const std::vector<std::vector<int>> perms = BruteForceRotations(p);
    size_t slots = 0;
    for (const std::string& r : roles) slots += r.empty() ? 1 : 0;
    if (slots == 0) continue;
    nontrivial += perms.size() > 1 ? 1 : 0;
    EXPECT_EQ(static_cast<size_t>(symmetry.effective_order()), perms.size()) << "layout " << layout;
    for (int n : {2, 3}) {
      EXPECT_EQ(CountIds(p, symmetry, n), BruteForceIds(perms, slots, n))
          << "layout " << layout << ", " << m << " patches, " << n << " colours";
    }
  }
  EXPECT_GE(nontrivial, 10);  // the check is not only on layouts without rotations
}

}  // namespace
}  // namespace patlab::detect

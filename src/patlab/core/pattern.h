// A planar patch pattern: circular colour patches at known model positions (mm), one of them the
// key patch that announces the pattern (paper section III). The model frame has x forward, y left;
// its origin is the point whose pose is reported.
#pragma once

#include <string>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/geometry.h"

namespace patlab {

// The most patches a pattern may have; estimators keep per-trial data in fixed-size arrays.
inline constexpr int kMaxPatches = 12;

enum class PatchRole {
  kKey,    // the key patch (exactly one per pattern): its colour is the team colour
  kId,     // an ID slot: its colour, from the codebook palette, encodes the pattern's ID
  kFixed,  // a fixed colour that is the same on every instance (e.g. a direction marker)
};

// How pattern files spell the roles (role = "key").
inline constexpr EnumNames<PatchRole, 3> kPatchRoleNames{{{
    {PatchRole::kKey, "key"},
    {PatchRole::kId, "id"},
    {PatchRole::kFixed, "fixed"},
}}};

struct Patch {
  Vec2 position_mm = Vec2::Zero();  // centre in the model frame
  double radius_mm = 0.0;           // > 0
  PatchRole role = PatchRole::kId;
  std::string colour;  // kFixed: its colour name; kKey: optional team colour; kId: empty
};

// The displacement from patch `from` to patch `to` is one orientation cue of the fast estimator.
struct OrientationPair {
  int from = 0;
  int to = 0;
  bool operator==(const OrientationPair&) const = default;
};

struct Pattern {
  std::string name;
  std::string description;
  std::vector<Patch> patches;                      // 2 .. kMaxPatches
  std::vector<OrientationPair> orientation_pairs;  // >= 1; defaults: see DefaultOrientationPairs
  int key_index = 0;                               // index of the kKey patch

  int size() const { return static_cast<int>(patches.size()); }
  // Mean of the model patch positions.
  Vec2 Centroid() const;
  // Sum of squared distances of the model patches from their centroid (mm^2): the geometric term
  // of the Cramer-Rao bound on the angle.
  double Spread() const;
};

// The paper's default choice of orientation pairs (section III): every pair (i, j), i < j, of
// non-key patches; or key -> the other patch when the pattern has only one non-key patch.
std::vector<OrientationPair> DefaultOrientationPairs(const std::vector<Patch>& patches,
                                                     int key_index);

}  // namespace patlab

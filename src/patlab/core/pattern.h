// A planar patch pattern: colour patches (discs or rectangles) at known model positions (mm), one
// of them the key patch that announces the pattern (paper section III). The model frame has x
// forward, y left; its origin is the point whose pose is reported.
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

// The outline of a patch. Discs are the paper's; rectangles are common in the Very Small Size
// League (a team-colour rectangle and an ID rectangle side by side on a 75 mm cube).
enum class PatchShape {
  kDisc,       // a disc of radius_mm
  kRectangle,  // a rectangle of size_mm, rotated by angle_rad
};
inline constexpr EnumNames<PatchShape, 2> kPatchShapeNames{{{
    {PatchShape::kDisc, "disc"},
    {PatchShape::kRectangle, "rectangle"},
}}};

struct Patch {
  Vec2 position_mm = Vec2::Zero();  // centre (= centroid, for both shapes) in the model frame
  // > 0. A disc's radius; for a rectangle the radius of the disc of equal area,
  // sqrt(size_x * size_y / pi), so that every use of the patch's area (the detector's area
  // tests, simulated blob areas) holds for both shapes.
  double radius_mm = 0.0;
  PatchRole role = PatchRole::kId;
  std::string colour;  // kFixed: its colour name; kKey: optional team colour; kId: empty
  PatchShape shape = PatchShape::kDisc;
  // kRectangle only: side lengths (mm) along the rectangle's own x and y axes, and the angle
  // (rad, counter-clockwise) from the model's x axis to the rectangle's x axis.
  Vec2 size_mm = Vec2::Zero();
  double angle_rad = 0.0;

  // The patch's area (mm^2): pi r^2, or size_x * size_y.
  double Area() const;
  // The radius of the smallest disc about the centre that holds the patch: r, or half the
  // rectangle's diagonal.
  double BoundingRadius() const;
  // Whether model point q lies inside or on the patch.
  bool Contains(const Vec2& q) const;
};

// A rectangle patch of the given size and angle centred at `centre` (radius_mm = equal-area).
Patch RectanglePatch(const Vec2& centre, const Vec2& size_mm, double angle_rad, PatchRole role,
                     std::string colour = "");

// How far apart two patches are (mm): the least distance between their outlines, > 0 when they
// are apart, 0 when they touch, < 0 when they overlap (then minus the least translation that
// separates them along the tested axes: disc-disc exact; rectangle-rectangle and rectangle-disc
// by the separating axis theorem, the disc tested along the rectangle's axes and the axis from
// its centre to the rectangle's nearest point).
double PatchGap(const Patch& a, const Patch& b);

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

// The layout search behind patlab design (design/design.h): impossible constraints, every output
// inside its constraints, criteria against independent recomputation, the known start beaten or
// equalled, determinism, and optima known in closed form.
#include "patlab/design/design.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tuple>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/design/compare.h"
#include "patlab/detect/codebook.h"

namespace patlab::design {
namespace {

// The file's precision: the geometric constraints hold to within it (docs/design.md).
constexpr double kFileMm = 1e-3;

DesignOptions Small(int starts = 6) {
  DesignOptions o;
  o.starts = starts;
  return o;
}

// sigma_theta >= sigma / sqrt(sum |p_i - pbar|^2) (estimate/bounds.h), in mrad per mm.
double AngleCrlbByHand(const Pattern& p) {
  Vec2 c = Vec2::Zero();
  for (const Patch& q : p.patches) c += q.position_mm;
  c /= p.size();
  double spread = 0;
  for (const Patch& q : p.patches) spread += (q.position_mm - c).squaredNorm();
  return 1e3 / std::sqrt(spread);
}

// The origin's per-axis bound: sigma sqrt(1/n + |pbar|^2 / (2 spread)) (estimate/bounds.h).
double PositionCrlbByHand(const Pattern& p) {
  Vec2 c = Vec2::Zero();
  for (const Patch& q : p.patches) c += q.position_mm;
  c /= p.size();
  double spread = 0;
  for (const Patch& q : p.patches) spread += (q.position_mm - c).squaredNorm();
  return std::sqrt(1.0 / p.size() + c.squaredNorm() / (2.0 * spread));
}

// Every constraint of the options, checked from the written pattern alone.
void ExpectMeetsConstraints(const DesignOptions& o, const DesignResult& r) {
  const Pattern& p = r.pattern;
  ASSERT_EQ(p.size(), o.id_patches + 1);
  EXPECT_EQ(p.patches[0].role, PatchRole::kKey);
  EXPECT_EQ(p.patches[0].position_mm, Vec2::Zero());
  for (int i = 0; i < p.size(); ++i) {
    const Patch& a = p.patches[i];
    EXPECT_LE(a.position_mm.norm() + a.radius_mm, o.outer_diameter_mm / 2 - o.rim_gap_mm + kFileMm)
        << i;
    for (int j = 0; j < i; ++j) {
      const Patch& b = p.patches[j];
      EXPECT_GE((a.position_mm - b.position_mm).norm() - a.radius_mm - b.radius_mm,
                o.min_gap_mm - kFileMm)
          << i << " " << j;
    }
  }
  const detect::Symmetry symmetry = detect::FindSymmetry(p, o.tolerance_mm);
  const uint64_t ids = detect::CountIds(p, symmetry, o.palette);
  const uint64_t required =
      o.min_ids > 0 ? static_cast<uint64_t>(o.min_ids)
                    : static_cast<uint64_t>(std::llround(std::pow(o.palette, o.id_patches)));
  EXPECT_GE(ids, required);
  const DesignGeometry g = ComputeDesignGeometry(p, symmetry);
  if (!std::isnan(g.rotation_onset_mm)) {
    EXPECT_GE(g.rotation_onset_mm, o.min_rotation_onset_mm);
  }
  EXPECT_LE(AngleCrlbByHand(p), o.max_angle_crlb_mrad_per_mm);
  EXPECT_LE(PositionCrlbByHand(p), o.max_position_crlb_per_mm);
  EXPECT_TRUE(r.metrics.feasible) << r.metrics.violated;
}

TEST(Design, ImpossibleConstraintsNameTheOption) {
  DesignOptions o;
  o.id_patches = 0;
  EXPECT_INPUT_ERROR(Validate(o), "id_patches is 0; expected an integer in [1, 11]");
  o = DesignOptions();
  o.palette = 1;
  EXPECT_INPUT_ERROR(Validate(o), "palette is 1; expected an integer in [2, 8]");
  o = DesignOptions();
  o.key_radius_mm = 100;
  EXPECT_INPUT_ERROR(Validate(o),
                     "key_radius_mm is 100; expected at most outer_diameter_mm / 2 - rim_gap_mm = "
                     "90 (the key patch must fit in the robot top)");
  o = DesignOptions();
  o.id_radii_mm = {30};
  EXPECT_INPUT_ERROR(Validate(o),
                     "id_radii_mm is 30; expected at most (outer_diameter_mm / 2 - rim_gap_mm - "
                     "key_radius_mm - min_gap_mm) / 2 = 22.5 (an ID patch must fit between the "
                     "key patch and the rim)");
  o = DesignOptions();
  o.id_radii_mm = {20, 20};
  EXPECT_INPUT_ERROR(Validate(o), "id_radii_mm has 2 values; expected 1 or id_patches (4)");
  // 11 dots of 20 mm with 10 mm around each: 11 pi 30^2 = 31102 mm^2 > pi (100^2 - 35^2).
  o = DesignOptions();
  o.id_patches = 11;
  EXPECT_INPUT_ERROR(Validate(o),
                     "id_patches is 11; expected fewer ID patches of these radii: with half of "
                     "min_gap_mm around each they cover 31102 mm^2, more than the 27567 mm^2 "
                     "between the key patch and the rim");
  o = DesignOptions();
  o.min_ids = 17;
  EXPECT_INPUT_ERROR(Validate(o), "min_ids is 17; expected an integer in [0, 16]");
  o = DesignOptions();
  o.name = "a/b";
  EXPECT_INPUT_ERROR(Validate(o),
                     "name is \"a/b\"; expected 1 to 100 letters, digits, '-', '_' or '.'");
}

TEST(Design, DotsThatCannotFitAfterTheSearch) {
  // 8 dots pass the area bound, but the ring for their centres is 5 mm wide and 8 chords of
  // 2 * 70 sin(pi / 8) = 53.6 mm < 60 mm cannot hold them: no start ends inside the robot top.
  DesignOptions o = Small(3);
  o.id_patches = 8;
  EXPECT_INPUT_ERROR(RunDesign(o),
                     "no layout of 8 ID patches fits with outer_diameter_mm 180, rim_gap_mm 0, "
                     "key_radius_mm 25 and min_gap_mm 20 (3 starts); expected fewer or smaller ID "
                     "patches, a smaller min_gap_mm or a larger outer_diameter_mm");
  // An impossible limit is the one named: with min_ids 1 no layout can fail on its IDs first
  // (which limit the search's best start misses otherwise depends on its path).
  o = Small(3);
  o.min_ids = 1;
  o.min_rotation_onset_mm = 100;
  EXPECT_INPUT_ERROR_STARTS_WITH(RunDesign(o),
                                 "no layout meets every limit (3 starts); the best inside the "
                                 "robot top by angle_crlb has rotation onset ");
  o = Small(3);
  o.min_ids = 1;
  o.max_position_crlb_per_mm = 0.4;  // never below 1 / sqrt(5) = 0.447 with 5 patches
  EXPECT_INPUT_ERROR_STARTS_WITH(RunDesign(o),
                                 "no layout meets every limit (3 starts); the best inside the "
                                 "robot top by angle_crlb has position CRLB ");
}

TEST(Design, EveryOutputMeetsItsConstraintsAndCriteriaMatchRecomputation) {
  std::vector<DesignOptions> cases(4, Small());
  cases[0].min_rotation_onset_mm = 3.5;
  cases[1].objective = DesignObjective::kRotationOnset;
  cases[1].max_angle_crlb_mrad_per_mm = 8.0;
  cases[2].id_patches = 3;
  cases[2].id_radii_mm = {15, 20, 25};
  cases[2].palette = 3;
  cases[2].objective = DesignObjective::kPositionCrlb;
  cases[2].outer_diameter_mm = 200;
  cases[3].id_patches = 5;
  cases[3].id_radii_mm = {15};
  cases[3].min_gap_mm = 10;
  cases[3].rim_gap_mm = 5;
  cases[3].palette = 3;
  cases[3].min_ids = 40;  // a 5-fold symmetric layout would have (3^5 - 3) / 5 = 48
  for (const DesignOptions& o : cases) {
    SCOPED_TRACE(NameOf(o.objective, kDesignObjectiveNames));
    const DesignResult r = RunDesign(o);
    ExpectMeetsConstraints(o, r);
    // The reported criteria are those of the pattern written, recomputed independently.
    const Pattern& p = r.pattern;
    EXPECT_NEAR(r.metrics.angle_crlb_mrad_per_mm, AngleCrlbByHand(p), 1e-9);
    EXPECT_NEAR(r.metrics.position_crlb_per_mm, PositionCrlbByHand(p), 1e-12);
    const detect::Symmetry symmetry = detect::FindSymmetry(p, o.tolerance_mm);
    EXPECT_EQ(r.metrics.ids, detect::CountIds(p, symmetry, o.palette));
    const DesignGeometry g = ComputeDesignGeometry(p, symmetry);
    if (std::isnan(g.rotation_onset_mm)) {
      EXPECT_TRUE(std::isinf(r.metrics.rotation_onset_mm));
    } else {
      EXPECT_NEAR(r.metrics.rotation_onset_mm, g.rotation_onset_mm, 1e-12);
    }
    EXPECT_GT(r.evaluations, 0);
    EXPECT_EQ(r.starts.size(), static_cast<size_t>(o.starts));
    // The pattern file reads back as the same pattern.
    const Pattern back = formats::ParsePattern(DesignPatternFileText(r), "design.toml");
    ASSERT_EQ(back.size(), p.size());
    for (int i = 0; i < p.size(); ++i) {
      EXPECT_EQ(back.patches[i].position_mm, p.patches[i].position_mm) << i;
      EXPECT_EQ(back.patches[i].radius_mm, p.patches[i].radius_mm) << i;
    }
  }
}

TEST(Design, BeatsOrEqualsTheKnownStart) {
  const Pattern ssl = testing::ShippedPattern("ssl-standard");
  DesignOptions o = Small(4);
  for (int slot : detect::IdSlots(ssl)) o.start_mm.push_back(ssl.patches[slot].position_mm);
  o.min_rotation_onset_mm = 3.4;  // the SSL standard's is 3.48 mm: the start is feasible
  const DesignMetrics start = EvaluateDesign(DesignPattern(o, o.start_mm), o);
  ASSERT_TRUE(start.feasible) << start.violated;
  const DesignResult r = RunDesign(o);
  EXPECT_TRUE(r.starts[0].from_options);
  EXPECT_LE(r.metrics.angle_crlb_mrad_per_mm, start.angle_crlb_mrad_per_mm);
  // And the other way round: the most robust layout at the standard's angle bound.
  o.objective = DesignObjective::kRotationOnset;
  o.max_angle_crlb_mrad_per_mm = start.angle_crlb_mrad_per_mm;
  const DesignResult robust = RunDesign(o);
  EXPECT_GE(robust.metrics.rotation_onset_mm, start.rotation_onset_mm);
  ExpectMeetsConstraints(o, robust);
}

TEST(Design, SameOptionsGiveIdenticalFiles) {
  DesignOptions o = Small(5);
  o.min_rotation_onset_mm = 2;
  const DesignResult a = RunDesign(o), b = RunDesign(o);
  EXPECT_EQ(DesignPatternFileText(a), DesignPatternFileText(b));
  EXPECT_EQ(DesignReportText(a), DesignReportText(b));
  o.seed = 2;
  EXPECT_NE(DesignReportText(RunDesign(o)), DesignReportText(a));  // the starts move
}

TEST(Design, OneIdPatchGoesToTheRim) {
  // Key at the origin and one dot at distance d: spread = d^2 / 2, so the angle CRLB
  // 1000 sqrt(2) / d falls with d and the optimum puts the dot against the rim:
  // d = 180 / 2 - 20 = 70 mm, 20.2031 mrad/mm. With one dot no rotation is wrong: every colour
  // is an ID and the onset is infinite.
  DesignOptions o = Small(4);
  o.id_patches = 1;
  const DesignResult r = RunDesign(o);
  EXPECT_NEAR(r.pattern.patches[1].position_mm.norm(), 70.0, kFileMm);
  EXPECT_NEAR(r.metrics.angle_crlb_mrad_per_mm, 1e3 * std::sqrt(2.0) / 70.0, 1e-4);
  EXPECT_EQ(r.metrics.ids, 2u);
  EXPECT_TRUE(std::isinf(r.metrics.rotation_onset_mm));
}

TEST(Design, TwoIdPatchesSpreadToTheLargestAngleGeometryCanTellApart) {
  // Key at the origin, dots at radius rho and rho' with angle alpha between them:
  // spread = |p1|^2 + |p2|^2 - |p1 + p2|^2 / 3, largest for rho = rho' = 70 mm (the rim), where
  // it is rho^2 (4 - 2 cos alpha) / 3, increasing in alpha up to pi. But at alpha = pi the
  // half-turn maps the layout onto itself and 2 colourings become 1 ID: every colouring (4) is an
  // ID only if the least-squares rotation about the key (theta = pi for cos alpha < 0) leaves a
  // dot farther than the 10 mm tolerance from its image, 2 rho sin((pi - alpha) / 2) > 10 mm. So
  // alpha* = pi - 2 asin(10 / (2 rho)), spread* = rho^2 (4 + 2 cos(2 asin(5 / rho))) / 3.
  DesignOptions o = Small(8);
  o.id_patches = 2;
  const DesignResult r = RunDesign(o);
  const double rho = 70.0, alpha = std::numbers::pi - 2.0 * std::asin(10.0 / (2.0 * rho));
  const double spread = rho * rho * (4.0 - 2.0 * std::cos(alpha)) / 3.0;
  EXPECT_EQ(r.metrics.ids, 4u);
  EXPECT_NEAR(r.pattern.patches[1].position_mm.norm(), rho, kFileMm);
  EXPECT_NEAR(r.pattern.patches[2].position_mm.norm(), rho, kFileMm);
  const Vec2 a = r.pattern.patches[1].position_mm, b = r.pattern.patches[2].position_mm;
  EXPECT_NEAR(std::acos(a.dot(b) / (a.norm() * b.norm())), alpha, 1e-4);
  EXPECT_NEAR(r.metrics.angle_crlb_mrad_per_mm, 1e3 / std::sqrt(spread), 1e-4);
}

// Symmetric families (--symmetry): the layout is in the family, the ID count is the symmetry
// rule's on the written (rounded, so near-symmetric) pattern, and the cyclic count matches the
// count of aperiodic colourings by hand.
TEST(Design, MirrorFamilyGivesMirrorLayoutsThatMeetTheirConstraints) {
  for (int n : {3, 4, 5}) {
    SCOPED_TRACE(n);
    DesignOptions o = Small(4);
    o.symmetry = DesignSymmetry::kMirror;
    o.id_patches = n;
    o.id_radii_mm = {15};
    o.min_gap_mm = 10;
    o.objective = DesignObjective::kRotationOnset;
    const DesignResult r = RunDesign(o);
    ExpectMeetsConstraints(o, r);
    const Pattern& p = r.pattern;
    for (int i = 1; i < p.size(); ++i) {
      const Vec2 mirror(p.patches[i].position_mm.x(), -p.patches[i].position_mm.y());
      double nearest = 1e9;
      for (int j = 1; j < p.size(); ++j) {
        nearest = std::min(nearest, (p.patches[j].position_mm - mirror).norm());
      }
      EXPECT_LE(nearest, 2 * kFileMm) << "patch " << i << " has no mirror image";
    }
    const detect::Symmetry symmetry = detect::FindSymmetry(p, o.tolerance_mm);
    EXPECT_EQ(r.metrics.ids, detect::CountIds(p, symmetry, o.palette));
    EXPECT_EQ(r.metrics.ids, static_cast<uint64_t>(std::llround(std::pow(2, n))));
    EXPECT_NE(DesignReportText(r).find(", symmetry mirror"), std::string::npos);
  }
}

TEST(Design, CyclicFamilyCountsOnlyAperiodicColourings) {
  // n ID patches on a regular polygon: every rotation by 360/n degrees is accepted, and an ID is
  // an orbit of n colourings with no rotational period: (c^n - periodic) / n. By hand:
  // n = 4, c = 2: (16 - 4 (0000, 1111, 0101, 1010)) / 4 = 3; n = 3, c = 3: (27 - 3) / 3 = 8.
  for (auto [n, c, want] : {std::tuple{4, 2, 3}, std::tuple{3, 3, 8}}) {
    SCOPED_TRACE(n);
    DesignOptions o = Small(3);
    o.symmetry = DesignSymmetry::kCyclic;
    o.id_patches = n;
    o.palette = c;
    o.min_ids = want;
    const DesignResult r = RunDesign(o);
    ExpectMeetsConstraints(o, r);
    EXPECT_EQ(r.metrics.ids, static_cast<uint64_t>(want));
    EXPECT_EQ(r.metrics.rotations, n);
    EXPECT_TRUE(std::isinf(r.metrics.rotation_onset_mm));  // colours decide every rotation
    const double rho = r.pattern.patches[1].position_mm.norm();
    for (int i = 2; i <= n; ++i) EXPECT_NEAR(r.pattern.patches[i].position_mm.norm(), rho, kFileMm);
    // The regular polygon farthest out (70 mm to the rim) spreads the patches most.
    EXPECT_NEAR(rho, 70.0, 2 * kFileMm);
  }
  DesignOptions all;
  all.symmetry = DesignSymmetry::kCyclic;  // min_ids 0: all 16, more than the 3 it can hold
  EXPECT_INPUT_ERROR(RunDesign(all),
                     "symmetry cyclic leaves 3 IDs with 2 colours; expected min_ids <= 3 (0 asks "
                     "for all 16)");
}

TEST(Design, SymmetryVariablesRoundTrip) {
  DesignOptions o;
  o.id_patches = 5;
  o.symmetry = DesignSymmetry::kMirror;
  ASSERT_EQ(SymmetryVariables(o), 5);
  const double x[5] = {10, 40, -30, 50, -60};
  const std::vector<Vec2> p = ExpandSymmetry(o, x);
  EXPECT_EQ(p[2], Vec2(10, -40));
  EXPECT_EQ(p[3], Vec2(-30, -50));
  EXPECT_EQ(p[4], Vec2(-60, 0));
  EXPECT_EQ(ReduceSymmetry(o, p), std::vector<double>(x, x + 5));
  o.symmetry = DesignSymmetry::kCyclic;
  ASSERT_EQ(SymmetryVariables(o), 2);
  const std::vector<Vec2> q = ExpandSymmetry(o, x);
  EXPECT_NEAR(q[1].x(),
              10 * std::cos(0.4 * std::numbers::pi) - 40 * std::sin(0.4 * std::numbers::pi), 1e-12);
  o.symmetry = DesignSymmetry::kNone;
  EXPECT_EQ(SymmetryVariables(o), 10);
}

}  // namespace
}  // namespace patlab::design

#include "patlab/design/compare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../expect_error.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/pattern_file.h"

namespace patlab::design {
namespace {

std::pair<Pattern, std::string> Design(const std::string& name) {
  const std::string file = std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name + ".toml";
  return {formats::LoadPatternFile(file), file};
}

CompareOptions SmallComparison() {
  CompareOptions o;
  o.evaluate.trials = 3000;
  o.evaluate.frames = 20;
  o.evaluate.sigmas_mm = {1.0, 4.0};
  return o;
}

// SSL standard, hand computed: dots of radius 20 at |p| = 65 mm -> diameter 2 (65 + 20) = 170;
// the smallest gap is key to dot, 65 - 25 - 20 = 20 mm. The nearest wrong rotation is a quarter
// turn, E0 = 932 mm^2 (docs/paper-reproduction.md, detect mode), chi2_7^-1(0.9999) = 29.88:
// sigma0 = sqrt(932 / 29.88) = 5.58 mm; the onset is sqrt(932 / lambda*) with
// P(ncx2(7, lambda*) <= 29.88) = 1e-3, lambda* = 65.713 (scipy, as in
// RotationOnsetIsTheExactNoncentralChiSquared): 3.766 mm (measured in frames: first rotation
// errors at 3.5-3.75 mm; the first-order approximation gave 3.48).
TEST(DesignGeometry, SslStandardByHand) {
  const auto [ssl, file] = Design("ssl-standard");
  const DesignGeometry g = ComputeDesignGeometry(ssl, detect::FindSymmetry(ssl, 10.0));
  EXPECT_NEAR(g.outer_diameter_mm, 170.0, 1e-3);
  EXPECT_NEAR(g.min_gap_mm, 20.0, 1e-3);
  EXPECT_NEAR(g.wrong_rotation_e0_mm2, 932.0, 1.0);
  EXPECT_NEAR(g.chi2_quantile, 29.88, 0.01);
  EXPECT_NEAR(g.rotation_sigma0_mm, 5.58, 0.01);
  EXPECT_NEAR(g.rotation_onset_mm, 3.766, 0.005);
}

// sigma with P(ncx2(dof, E0 / sigma^2) <= chi2) = 1e-3, from scipy 1.10.1 (computed once):
//   from scipy.stats import ncx2, chi2; from scipy.optimize import brentq; import math
//   q = chi2.ppf(0.9999, dof)
//   lam = brentq(lambda l: ncx2.cdf(q, dof, l) - 0.001, 1e-9, 1e4, xtol=1e-14, rtol=1e-15)
//   math.sqrt(e0 / lam)
// The first-order normal approximation gave 1.1383, 2.3954, 0.7906, 0.4072: 7-11% lower.
TEST(DesignGeometry, RotationOnsetIsTheExactNoncentralChiSquared) {
  struct Case {
    double e0;
    int dof;
    double chi2, sigma;
  };
  const Case cases[] = {{100.0, 7, 29.87750390922517, 1.2335976680836076},
                        {400.0, 3, 21.107513466160444, 2.6612989245414997},
                        {50.0, 9, 33.719948438964906, 0.8496552255718339},
                        {12.25, 5, 25.74483195905612, 0.445965205749033}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.dof);
    EXPECT_NEAR(RotationOnsetSigma(c.e0, c.dof, c.chi2), c.sigma, 1e-7 * c.sigma);
  }
  EXPECT_EQ(RotationOnsetSigma(0.0, 7, 29.87750390922517), 0.0);
}

TEST(DesignGeometry, ColoursDecideEveryRotationOfTheTriangle) {
  const auto [triangle, file] = Design("triangle");
  const DesignGeometry g = ComputeDesignGeometry(triangle, detect::FindSymmetry(triangle, 10.0));
  EXPECT_TRUE(std::isinf(g.wrong_rotation_e0_mm2));
  EXPECT_TRUE(std::isnan(g.rotation_sigma0_mm));
  EXPECT_TRUE(std::isnan(g.rotation_onset_mm));
}

TEST(CompareDesigns, RanksByTheChosenColumnBestFirst) {
  CompareOptions o = SmallComparison();
  o.sort_by = "ids_2c";
  const CompareResult r =
      CompareDesigns({Design("triangle"), Design("butterfly"), Design("linear")}, o);
  ASSERT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(r.rows[0].design, "butterfly");  // 16 IDs
  EXPECT_EQ(r.rows[1].design, "triangle");   // 2
  EXPECT_EQ(r.rows[2].design, "linear");     // 1
  EXPECT_EQ(r.rows[2].rank, 3);
  o.sort_by = "crlb_theta_mrad_per_mm";  // smaller is better: the butterfly's four dots
  const CompareResult by_angle = CompareDesigns({Design("linear"), Design("butterfly")}, o);
  EXPECT_EQ(by_angle.rows[0].design, "butterfly");
}

TEST(CompareDesigns, SameNumbersForAnyThreadCountAndAnyCompanions) {
  CompareOptions o = SmallComparison();
  o.evaluate.threads = 1;
  const CompareResult one = CompareDesigns({Design("ssl-standard"), Design("triangle")}, o);
  o.evaluate.threads = 2;
  const CompareResult two = CompareDesigns({Design("ssl-standard"), Design("triangle")}, o);
  EXPECT_EQ(CompareCsv(one), CompareCsv(two));
  EXPECT_EQ(CompareText(one), CompareText(two));
  // A design's numbers do not depend on which designs it is compared with.
  const CompareResult alone = CompareDesigns({Design("triangle")}, o);
  const CompareRow& with = one.rows[0].design == "triangle" ? one.rows[0] : one.rows[1];
  ASSERT_EQ(alone.rows[0].cells.size(), with.cells.size());
  for (size_t k = 0; k < with.cells.size(); ++k) {
    const auto& [name, value] = with.cells[k];
    EXPECT_EQ(alone.rows[0].cells[k].first, name);
    const double a = alone.rows[0].cells[k].second;
    EXPECT_TRUE(a == value || (std::isnan(a) && std::isnan(value))) << name;  // bit for bit
  }
}

TEST(CompareDesigns, ProgressCountsEveryRunOnce) {
  CompareOptions o = SmallComparison();
  std::vector<std::pair<int, int>> calls;
  o.progress = [&](int done, int total) { calls.push_back({done, total}); };
  CompareDesigns({Design("simple"), Design("linear")}, o);
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls.back(), std::make_pair(6, 6));  // 2 designs x (1 Monte-Carlo + 2 sigmas)
  for (size_t k = 1; k < calls.size(); ++k) EXPECT_GE(calls[k].first, calls[k - 1].first);
}

TEST(CompareDesigns, BadInputNamesWhatAndWhere) {
  auto [no_ids, file] = Design("simple");
  no_ids.patches[1].role = PatchRole::kFixed;
  no_ids.patches[1].colour = "red";
  EXPECT_INPUT_ERROR(CompareDesigns({{no_ids, "x.toml"}}, SmallComparison()),
                     "x.toml: design simple has no ID slots; expected at least one patch with "
                     "role = \"id\"");
  EXPECT_INPUT_ERROR(
      CompareDesigns({Design("simple"), {Design("simple").first, "y.toml"}}, SmallComparison()),
      "y.toml: design name \"simple\" is also the name in " + std::string(PATLAB_SOURCE_DIR) +
          "/patterns/simple.toml; expected distinct design names");
  CompareOptions o = SmallComparison();
  o.sort_by = "speed";
  o.evaluate.colour_counts = {2};
  o.evaluate.sigmas_mm = {2.0};
  EXPECT_INPUT_ERROR(
      CompareDesigns({Design("simple")}, o),
      "--sort-by is \"speed\"; expected one of: diameter_mm, min_gap_mm, rotations, "
      "crlb_pos_per_mm, fast_pos_per_mm, ml_pos_per_mm, crlb_theta_mrad_per_mm, "
      "fast_theta_mrad_per_mm, ml_theta_mrad_per_mm, fast_eff_pos, fast_eff_theta, ids_2c, "
      "rotation_sigma0_mm, rotation_onset_mm, detection_2mm, wrong_id_2mm, "
      "ambiguous_2mm, rotation_errors_2mm");
}

}  // namespace
}  // namespace patlab::design

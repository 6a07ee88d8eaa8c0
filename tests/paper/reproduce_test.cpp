// The comparison behind `patlab reproduce --check` (src/patlab/paper/reproduce.h).
#include "patlab/paper/reproduce.h"

#include <cmath>

#include <gtest/gtest.h>

namespace patlab::paper {
namespace {

TEST(Reproduce, CompareResultTextAcceptsTheCrossMachineToleranceOnly) {
  const std::string a = "pattern,std_mm,trials\nsimple,0.8680123456,100000\nlinear,,5\n";
  EXPECT_EQ(CompareResultText(a, a), "");
  // One unit in the 10th digit is within 2e-9 relative.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123457,100000\nlinear,,5\n"),
            "");
  // Two units in the 7th digit are not.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680143456,100000\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simple,0.8680143456,100000");
  // A count that moves by one, an empty cell that fills, a text cell that changes.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123456,100001\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simple,0.8680123456,100001");
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123456,100000\nlinear,1,5\n"),
            "line 3: linear,,5; committed: linear,1,5");
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimplx,0.8680123456,100000\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simplx,0.8680123456,100000");
  // Rounding noise near zero (the sigma = 0 rows) within 1e-12 absolute.
  EXPECT_EQ(CompareResultText("m\n1.2e-13\n", "m\n-3.1e-13\n"), "");
  EXPECT_EQ(CompareResultText("m\n1.2e-13\n", "m\n"), "line 2: extra line 1.2e-13");
  EXPECT_EQ(CompareResultText("m\n", "m\n7\n"), "line 2: missing line 7");
}

// Hand-counted: d = |a| - |b| = 0.5, -0.5, 0.5, 0, 0.25 (+ a few ulp), -0.25. The three |d| = 0.5
// are one tie cluster (2 positive, 1 negative: 2 opposite pairs, 3^3 - 3 = 24), the two |d| =
// 0.25 a knife edge apart another (1 pair, 6), the zero a near-zero difference.
TEST(ReproduceCompare, KnifeEdgeAllowanceCountsOppositeSignPairsWithinTheDrift) {
  const std::vector<double> a = {1.0, 2.0, 3.0, 5.0, 1.25 + 4e-16, 1.0};
  const std::vector<double> b = {0.5, 2.5, 2.5, 5.0, 1.0, 1.25};
  const RankAllowance r = KnifeEdgeAllowance(a, b);
  EXPECT_EQ(r.pairs, 6.0);
  EXPECT_EQ(r.near_zero, 1.0);
  EXPECT_EQ(r.opposite_pairs, 3.0);
  EXPECT_EQ(r.tie_term, 30.0);
  EXPECT_EQ(r.RankSumMove(), 3.0 + 6.0);
  // 0.25 and 0.25 + 1e-9 are not a knife edge (1e-9 >> 1e-12 of the values): no pair.
  const RankAllowance apart =
      KnifeEdgeAllowance(std::vector<double>{1.25 + 1e-9, 1.0}, std::vector<double>{1.0, 1.25});
  EXPECT_EQ(apart.opposite_pairs, 0.0);
  EXPECT_EQ(apart.near_zero, 0.0);
}

// A fig5.csv with a few of its columns: a sigma = 0 row, an exact-ML row (Simple: the ML's stds
// are the fast ones), a Butterfly row whose ML moves the trials.
const std::string kFig5Header =
    "pattern,estimator,sigma_mm,trials,noise,std_x_mm,std_y_mm,std_theta_rad,ml_nonconverged,"
    "ml_first_nonconverged_trial,ml_mean_iterations,ks_x_d,ks_x_p,wilcoxon_pos_p\n";
std::string Fig5(const std::string& ml_zero, const std::string& ml_simple,
                 const std::string& ml_butterfly) {
  return kFig5Header + "simple,fast,0,100000,isotropic,6.7e-14,5.3e-14,5.7e-16,,,,,,\n" + ml_zero +
         "\nsimple,fast,1,100000,isotropic,0.61,0.62,0.0218,,,,,,\n" + ml_simple +
         "\nbutterfly,fast,1,100000,isotropic,0.45,0.46,0.0078,,,,,,\n" + ml_butterfly + "\n";
}
const std::string kZero = "simple,ml,0,100000,isotropic,8.7e-14,6.9e-14,1.4e-15,0,-1,0.62426,,,";
const std::string kSimple = "simple,ml,1,100000,isotropic,0.61,0.62,0.0218,0,-1,0.65543,1e-05,1,1";
const std::string kButterfly =
    "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,0,-1,2.57764,0.0031,0.7225549558,0.3";

std::string CompareFig5(const std::string& zero, const std::string& simple,
                        const std::string& butterfly) {
  return CompareResultCsv(Fig5(kZero, kSimple, kButterfly), Fig5(zero, simple, butterfly),
                          RulesForResultFile("results/fig5.csv"));
}

TEST(ReproduceCompare, Fig5KnifeEdgeChangesPass) {
  EXPECT_EQ(CompareFig5(kZero, kSimple, kButterfly), "");
  // The clang build's sigma = 0 row: every trial's 0 or 1 Newton step is decided by rounding.
  EXPECT_EQ(CompareFig5("simple,ml,0,100000,isotropic,8.7e-14,6.9e-14,1.4e-15,0,-1,0.59666,,,",
                        kSimple, kButterfly),
            "");
  // The same in an exact-ML row at sigma > 0, and its D by one sample (p stays 1).
  EXPECT_EQ(CompareFig5(kZero, "simple,ml,1,100000,isotropic,0.61,0.62,0.0218,0,-1,0.2,2e-05,1,1",
                        kButterfly),
            "");
  // One knife-edge trial in the Butterfly row: one non-converged trial (and its index),
  // D by 1/n and the p-values that implies, the std in its 10th digit; the mean iteration
  // count by 0.00193, as the clang build's at sigma = 0.25 (2.25348 against 2.25155).
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090480,0.46,0.0077,1,4711,2.57571,"
                        "0.00311,0.7188503209,0.3045"),
            "");
}

TEST(ReproduceCompare, Fig5RealEditsFailNamingLineColumnValuesAndTolerance) {
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503094982,0.46,0.0077,0,-1,2.57764,"
                        "0.0031,0.7225549558,0.3"),
            "line 7, column std_x_mm (continuous): 0.4503090479 vs committed 0.4503094982; "
            "tolerance +-9.01619e-10 (relative drift 2e-9 + 1e-12)");
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,0,-1,3.6,"
                        "0.0031,0.7225549558,0.3"),
            "line 7, column ml_mean_iterations (mean count): 2.57764 vs committed 3.6; "
            "tolerance +-1 (each trial's last step is decided by a gradient at rounding level: one "
            "step)");
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,2,-1,2.57764,"
                        "0.0031,0.7225549558,0.3"),
            "line 7, column ml_nonconverged (count): 0 vs committed 2; tolerance +-1 (knife-edge "
            "events)");
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,0,17,2.57764,"
                        "0.0031,0.7225549558,0.3"),
            "line 7, column ml_first_nonconverged_trial (first trial): -1 vs committed 17; "
            "tolerance exact unless the row's count moved");
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,0,-1,2.57764,"
                        "0.0031,0.7225549558,0.32"),
            "line 7, column wilcoxon_pos_p (Wilcoxon p): 0.3 vs committed 0.32; tolerance allowed "
            "[0.292389, 0.307742] (z +-0.0165: a difference crossing the zero threshold)");
  EXPECT_EQ(CompareFig5(kZero, kSimple,
                        "butterfly,ml,1,100000,isotropic,0.4503090479,0.46,0.0077,0,-1,2.57764,"
                        "0.00313,0.7225549558,0.3"),
            "line 7, column ks_x_d (KS D): 0.0031 vs committed 0.00313; tolerance +-1e-05 "
            "(knife-edge samples / trials)");
  // A mean iteration count outside [0, 1] where the ML starts at its optimum, a text cell.
  EXPECT_EQ(
      CompareFig5("simple,ml,0,100000,isotropic,8.7e-14,6.9e-14,1.4e-15,0,-1,1.2,,,", kSimple,
                  kButterfly),
      "line 3, column ml_mean_iterations (mean count): 0.62426 vs committed 1.2; tolerance both in "
      "[0, 1] (the ML starts at its optimum up to rounding: 0 or 1 step)");
  EXPECT_EQ(
      CompareFig5(kZero, "simplx,ml,1,100000,isotropic,0.61,0.62,0.0218,0,-1,0.65543,1e-05,1,1",
                  kButterfly),
      "line 5, column pattern (text): simple vs committed simplx; tolerance exact (text)");
}

// table1_tests.csv's row that flipped ties under clang: R+ and R- moved by 16.5.
const std::string kTestsHeader =
    "error,axis,a,b,n,median_abs_a_mm,median_abs_b_mm,r_plus,r_minus,z,p_value,smaller\n";
const std::string kGccRow =
    "true,x,40mm,50mm,12450,0.3622,0.3395,41865163,35642312,-7.758,8.6e-15,50mm\n";
const std::string kClangRow =
    "true,x,40mm,50mm,12450,0.3622,0.3395,41865179.5,35642295.5,-7.758,8.6e-15,50mm\n";

std::string CompareTests(const std::string& regenerated, const std::string& committed,
                         double opposite_pairs) {
  CsvRules rules = RulesForResultFile("track_quantisation/table1_tests.csv");
  RankAllowance a;
  a.pairs = 12450;
  a.opposite_pairs = opposite_pairs;
  a.tie_term = 6.0 * opposite_pairs;
  rules.rank_allowances["true,x,40mm,50mm"] = a;
  return CompareResultCsv(kTestsHeader + regenerated, kTestsHeader + committed, rules);
}

TEST(ReproduceCompare, RankSumsMoveByTheirKnifeEdgePairsOnly) {
  EXPECT_EQ(CompareTests(kClangRow, kGccRow, 17.0), "");
  EXPECT_EQ(CompareTests(kClangRow, kGccRow, 16.0),
            "line 2, column r_plus (rank sum): 41865179.5 vs committed 41865163; tolerance +-16 "
            "(16 knife-edge opposite-sign pairs, 0 near-zero differences)");
  // A rank sum edited by 10000, a z and a p that the allowed move cannot explain.
  EXPECT_EQ(
      CompareTests(kGccRow,
                   "true,x,40mm,50mm,12450,0.3622,0.3395,41875163,35632312,-7.758,8.6e-15,50mm\n",
                   17.0),
      "line 2, column r_plus (rank sum): 41865163 vs committed 41875163; tolerance +-17 (17 "
      "knife-edge opposite-sign pairs, 0 near-zero differences)");
  EXPECT_EQ(
      CompareTests(kGccRow,
                   "true,x,40mm,50mm,12450,0.3622,0.3395,41865163,35642312,-7.761,8.6e-15,50mm\n",
                   17.0),
      "line 2, column z (Wilcoxon z): -7.758 vs committed -7.761; tolerance +-0.00104239 (17 "
      "knife-edge opposite-sign pairs, 0 near-zero differences; plus one printed unit)");
  EXPECT_EQ(CompareTests(kGccRow,
                         "true,x,40mm,50mm,12450,0.3622,0.3395,41865163,35642312,-7.759,"
                         "8.65e-15,50mm\n",
                         17.0),
            "");
  EXPECT_EQ(
      CompareTests(kGccRow,
                   "true,x,40mm,50mm,12450,0.3622,0.3395,41865163,35642312,-7.758,8.7e-15,50mm\n",
                   17.0),
      "line 2, column p_value (normal p): 8.6e-15 vs committed 8.7e-15; tolerance allowed "
      "[8.5811e-15, 8.67488e-15] (z +-0.000542 from 17 knife-edge opposite-sign pairs, 0 "
      "near-zero differences; plus one printed unit)");
  // Without knife edges the rank sums must agree exactly; a row without an allowance fails.
  EXPECT_EQ(CompareTests(kClangRow, kGccRow, 0.0),
            "line 2, column r_plus (rank sum): 41865179.5 vs committed 41865163; tolerance +-0 (0 "
            "knife-edge opposite-sign pairs, 0 near-zero differences)");
  EXPECT_EQ(CompareResultCsv(kTestsHeader + kClangRow, kTestsHeader + kGccRow,
                             RulesForResultFile("table1_tests.csv")),
            "line 2, column r_plus (rank sum): 41865179.5 vs committed 41865163; tolerance no "
            "rank allowance for this row");
  EXPECT_EQ(CompareResultCsv("a,b\n1,2\n", "a,b\n1,2\n", RulesForResultFile("table1.csv")),
            "line 1: column a has no rule");
}

}  // namespace
}  // namespace patlab::paper

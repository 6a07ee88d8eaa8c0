// Coverage of the std's 95% interval in `patlab analyze` (analysis/analyze.h) on autocorrelated
// errors: a straight track plus AR(1) noise x_t = phi x_{t-1} + e_t (stationary, marginal std 1),
// 200 seeded replicates per phi and detrending. The interval on the effective dof
// (error_stats.h) must cover what the std estimates in >= 90% of them (the target; nominal 95%);
// the iid interval covers far less at phi = 0.9, so the test would fail without the correction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "patlab/analysis/analyze.h"
#include "patlab/core/rng.h"
#include "patlab/stats/smoothing.h"

namespace patlab::analysis {
namespace {

constexpr int kReplicates = 200;
constexpr int kSamples = 2000;

// A track along x at `speed` mm per frame with AR(1) errors of marginal std 1 on x and y.
MeasuredTrack Ar1Track(double phi, uint64_t replicate, double speed) {
  RandomStream rng(30, 4, replicate + 1000 * static_cast<uint64_t>(phi * 10));
  MeasuredTrack t{.subject = "a",
                  .run = "r",
                  .file = "ar1.csv",
                  .first_line = 2,
                  .frame = {},
                  .x = {},
                  .y = {},
                  .theta = {}};
  const double innovation = std::sqrt(1.0 - phi * phi);
  double ex = rng.Normal(), ey = rng.Normal();
  for (int f = 0; f < kSamples; ++f) {
    if (f > 0) {
      ex = phi * ex + innovation * rng.Normal();
      ey = phi * ey + innovation * rng.Normal();
    }
    t.frame.push_back(f);
    t.x.push_back(100.0 + speed * f + ex);
    t.y.push_back(-50.0 + ey);
  }
  return t;
}

// The std of the smoothing residual r_t = x_t - sum_j w_j x_{t+j} of a stationary AR(1) of
// marginal std 1: with a = delta - w (w the full symmetric kernel), Var r = sum_jk a_j a_k
// phi^|j - k|. This, not 1, is what the smoothed estimate's interval is for.
double SmoothedResidualStd(double phi, const stats::SmoothingOptions& smoothing) {
  const std::vector<double> half = stats::GaussianKernel(smoothing);
  const int radius = static_cast<int>(half.size()) - 1;
  std::vector<double> a(static_cast<size_t>(2 * radius + 1));
  for (int j = -radius; j <= radius; ++j) {
    a[static_cast<size_t>(j + radius)] =
        (j == 0 ? 1.0 : 0.0) - half[static_cast<size_t>(std::abs(j))];
  }
  double var = 0.0;
  for (size_t j = 0; j < a.size(); ++j) {
    for (size_t k = 0; k < a.size(); ++k) {
      var += a[j] * a[k] * std::pow(phi, std::abs(static_cast<double>(j) - static_cast<double>(k)));
    }
  }
  return std::sqrt(var);
}

struct Coverage {
  double effective = 0.0, iid = 0.0;
};

Coverage Measure(double phi, Detrend detrend) {
  AnalyzeOptions o;
  o.detrend = detrend;
  const double truth = detrend == Detrend::kSmooth ? SmoothedResidualStd(phi, o.smoothing) : 1.0;
  int covered = 0, covered_iid = 0;
  for (int r = 0; r < kReplicates; ++r) {
    // detrend none: a subject at rest; the others: moving at 7 mm per frame.
    const double speed = detrend == Detrend::kNone ? 0.0 : 7.0;
    const AnalyzeReport report = AnalyzeTracks({Ar1Track(phi, static_cast<uint64_t>(r), speed)}, o);
    const stats::ErrorSummary& e = report.subjects.at(0).est;
    for (const auto& [ci, iid] : {std::pair(e.x, e.x_iid), std::pair(e.y, e.y_iid)}) {
      covered += ci.lower <= truth && truth <= ci.upper;
      covered_iid += iid.lower <= truth && truth <= iid.upper;
    }
  }
  return {covered / (2.0 * kReplicates), covered_iid / (2.0 * kReplicates)};
}

// 200 replicates x 2 axes per cell: a binomial SE of 1.1% about 95%; >= 90% is the target.
TEST(AnalyzeCoverage, EffectiveIntervalCoversAr1StdsUpToPhiNineTenths) {
  for (const Detrend detrend : {Detrend::kSmooth, Detrend::kLinear, Detrend::kNone}) {
    for (const double phi : {0.0, 0.5, 0.9}) {
      const Coverage c = Measure(phi, detrend);
      std::printf("detrend %-6s phi %.1f: coverage %.3f (iid interval %.3f)\n",
                  std::string(NameOf(detrend, kDetrendNames)).c_str(), phi, c.effective, c.iid);
      SCOPED_TRACE(std::string(NameOf(detrend, kDetrendNames)) + " phi " + std::to_string(phi));
      EXPECT_GE(c.effective, 0.90);
      EXPECT_LE(c.effective, 0.99);  // not covered by being needlessly wide
      if (phi == 0.9) {
        EXPECT_LT(c.iid, 0.70);
      }
    }
  }
}

// The interval at phi = 0 is the iid one up to the noise in tau (tau is 1 + 2 sum r_k^2 over the
// lags outside the white-noise band, which white noise leaves only by chance).
TEST(AnalyzeCoverage, WhiteErrorsKeepNearlyTheIidInterval) {
  AnalyzeOptions o;
  o.detrend = Detrend::kNone;
  const AnalyzeReport report = AnalyzeTracks({Ar1Track(0.0, 7, 0.0)}, o);
  const stats::ErrorSummary& e = report.subjects.at(0).est;
  EXPECT_LT(e.size_x.tau, 1.02);
  EXPECT_NEAR(e.x.upper - e.x.lower, e.x_iid.upper - e.x_iid.lower,
              0.02 * (e.x_iid.upper - e.x_iid.lower));
  EXPECT_TRUE(report.warnings.empty());
}

// AR(1) at phi = 0.9: tau ~ (1 + phi^2) / (1 - phi^2) = 9.5, so the iid interval is ~3x too
// narrow: a warning names the subject and the axis.
TEST(AnalyzeCoverage, StronglyCorrelatedErrorsWarn) {
  AnalyzeOptions o;
  o.detrend = Detrend::kLinear;
  const AnalyzeReport report = AnalyzeTracks({Ar1Track(0.9, 3, 7.0)}, o);
  ASSERT_EQ(report.warnings.size(), 2u);
  EXPECT_NE(report.warnings[0].find("subject \"a\", est x: lag-1 autocorrelation 0.9"),
            std::string::npos)
      << report.warnings[0];
  EXPECT_GT(report.subjects[0].est.size_x.tau, 7.0);
}

TEST(AnalyzeCoverage, AlongTravelNeedsATrend) {
  AnalyzeOptions o;
  o.detrend = Detrend::kNone;
  o.along_travel = true;
  ASSERT_EQ(Check(o).size(), 1u);
  EXPECT_EQ(Check(o)[0].message,
            "along_travel is true with detrend \"none\"; expected detrend \"smooth\" or "
            "\"linear\" (a mean has no direction of travel)");
}

}  // namespace
}  // namespace patlab::analysis

// The experiment runner: every pattern x patch sigma is a data point of `trials` random poses;
// every chosen estimator runs on the same noisy patches; per point and estimator the error
// statistics, the Cramer-Rao bound and the first-order predicted std, and (for every estimator
// but fast) the KS and Wilcoxon comparison with the fast estimator.
#pragma once

#include <tbb/global_control.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "patlab/estimate/bounds.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/experiment.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::sim {

// Share `index` of `count` of a sweep's points (both 1-based, 1 <= index <= count <=
// kMaxShards; shard.h); 1/1, the default, is the whole sweep.
struct ShardSpec {
  int index = 1;
  int count = 1;
  bool IsWhole() const { return count == 1; }
  // True when grid point `point` belongs to this share: point mod count = index - 1.
  bool Holds(int64_t point) const { return point % count == index - 1; }
};
inline constexpr int kMaxShards = 100000;
// The most worker threads a run takes: more is a typo, and each thread costs its buffers.
inline constexpr int kMaxThreads = 4096;

// Bounded memory (docs/hardening.md): a data point is run in blocks of at most this many trials
// (or frames, in detect mode), and only one block's samples are held per estimator, so memory
// stops growing with the trials asked for beyond one block. Each block's moments come from its
// samples (stats::PlanarMomentsOfEach) and the blocks are combined in trial order
// (stats::CombineMoments); a point of one block gets exactly the bits of the whole-sample
// computation. The KS and Wilcoxon comparisons need the samples themselves: they are computed on
// the first block, trials 0 .. min(trials, kStatisticsBlockTrials) - 1 (Comparison::trials).
inline constexpr int64_t kStatisticsBlockTrials = int64_t{1} << 20;
inline constexpr int64_t kStatisticsBlockFrames = int64_t{1} << 14;
// Blocks of at most this many trials keep two sets of sample arrays, so that the statistics of
// one overlap the trials of the next (at most 2^17 x 24 bytes = 3 MB more per estimator); larger
// blocks keep one set and wait for the statistics.
inline constexpr int64_t kOverlapMaxTrials = int64_t{1} << 17;

// One block of a data point: trials (frames) first .. first + count - 1 of point `point`, the
// unit of work of both runners and of a share (shard.h).
struct WorkBlock {
  int64_t point = 0;  // grid index
  int64_t block = 0;  // 0-based within the point
  int64_t first = 0;
  int64_t count = 0;
};
// ceil(per_point / block_size): the blocks of a point of `per_point` trials (frames).
int64_t BlocksPerPoint(int64_t per_point, int64_t block_size);
// The blocks share K/N runs of a sweep of `points` points: block b of point p is item
// i = p * BlocksPerPoint + b, and item i belongs to share (i mod N) + 1 (so a point of one block
// is a whole point, as before), in item order.
std::vector<WorkBlock> ShareBlocks(int64_t points, int64_t per_point, int64_t block_size,
                                   const ShardSpec& shard);

struct RunOptions {
  int threads = 0;  // worker threads; 0 = all cores. Results do not depend on it.
  ShardSpec shard;  // only the points of this share are run (RunResult::points holds them)
  // Called on the calling thread after each block of trials or frames: (blocks done, blocks in
  // all); a point of at most one block (the usual case) is one block.
  std::function<void(int, int)> progress;
};
// threads an integer >= 0, shard 1 <= index <= count <= kMaxShards; both runners validate their
// options.
std::vector<OptionsProblem> Check(const RunOptions& options);
void Validate(const RunOptions& options);

// The worker threads a run uses (options.threads, or every core for 0) and the TBB limit that
// holds them to it while it lives: both runners start with one.
class ThreadLimit {
 public:
  explicit ThreadLimit(const RunOptions& options);
  int threads() const { return threads_; }

 private:
  int threads_;
  std::unique_ptr<tbb::global_control> limit_;
};

// Sample std of one error component with its 95% chi-square interval, and the mean (the bias).
struct AxisSummary {
  double mean = 0.0;
  double std = 0.0;
  double std_lower = 0.0;
  double std_upper = 0.0;
};

// The estimator against fast on the same trials: two-sample KS of the x, y and theta errors
// (two-sided, asymptotic at these sizes), and the Wilcoxon signed-rank test of the paired
// absolute errors (|position error|, |theta error|; two-sided, normal approximation with tie
// correction). Not computed at sigma = 0, where all errors are rounding noise.
struct Comparison {
  bool computed = false;
  int64_t trials = 0;  // the trials compared: the first min(trials, kStatisticsBlockTrials)
  stats::KsResult ks_x, ks_y, ks_theta;
  stats::WilcoxonResult wilcoxon_position, wilcoxon_theta;
};

struct EstimatorResult {
  estimate::Estimator estimator = estimate::Estimator::kFast;
  AxisSummary x, y, theta;             // world-frame errors (mm, mm, rad)
  double position_std_mm = 0.0;        // per-axis std pooled over x and y: sqrt((vx + vy) / 2)
  double position_std_lower_mm = 0.0;  // its 95% interval (chi-square, 2(n - 1) dof)
  double position_std_upper_mm = 0.0;
  double radial_rms_mm = 0.0;     // sqrt(mean(ex^2 + ey^2)), bias included
  AxisSummary radial;             // |position error| = sqrt(ex^2 + ey^2): mean, std, 95% CI
  double crlb_position_mm = 0.0;  // Cramer-Rao bound, per axis (isotropic Gaussian only)
  double crlb_theta_rad = 0.0;
  double predicted_position_mm = 0.0;  // first-order predicted std of this estimator
  double predicted_theta_rad = 0.0;
  // ml and robust: trials whose iteration did not converge (Newton; robust's IRLS / EM: 200
  // steps without a step below 1e-9 mm and 1e-11 rad), the first of them to replay (-1: none),
  // and the mean steps.
  int64_t nonconverged = 0;
  int64_t first_nonconverged_trial = -1;
  double mean_iterations = 0.0;
  Comparison vs_fast;
};

// Mean, std (divisor n - 1) and its 95% chi-square interval of a sample summarised by its
// moments; the std and interval are NaN below 2 values, the mean below 1.
AxisSummary SummariseMoments(const stats::Moments& m);

// Efficiency = bound^2 / achieved^2 (1 = efficient); NaN without a bound (NaN) or without a
// positive achieved std.
double Efficiency(double bound, double achieved);

struct PointResult {
  int pattern_index = 0;
  std::string pattern;
  double sigma_mm = 0.0;
  uint32_t point = 0;  // index in this run's grid, pattern_index * num_sigmas + sigma_index (for
                       // --replay); the trials are keyed by KnownPointKey, not by this index
  int64_t trials = 0;
  std::vector<EstimatorResult> estimators;  // in experiment order
};

// What one block of a point's trials leaves for one estimator: the moments of its errors and its
// ML counters, and (the first block only) the comparison with fast. A point's blocks fold in
// trial order into its EstimatorResult (FinishPoint).
struct EstimatorBlock {
  stats::Moments x, y, theta, radial;
  double sum_sq = 0.0;  // sum of ex^2 + ey^2 (the radial RMS)
  int64_t iterations = 0, nonconverged = 0;
  int64_t first_nonconverged_trial = -1;  // a trial index of the point
  Comparison vs_fast;                     // the first block's (computed = false elsewhere)
};
struct PointBlock {
  WorkBlock work;
  std::vector<EstimatorBlock> estimators;  // in experiment order
};

// The point's result from all its blocks (block 0, 1, ... in order). `header` holds the point's
// identity (pattern, sigma, trials, point) and, per estimator, the estimator and its bounds
// (crlb_*, predicted_*), which are copied; everything else comes from the blocks. The runner
// and `patlab merge` both finish points here, so a merged point has the runner's bits.
PointResult FinishPoint(const PointResult& header, std::span<const PointBlock> blocks);

struct RunResult {
  std::vector<PointResult> points;  // pattern-major, then sigma (only the share's, if sharded)
  // A sharded run whose points have more than one block: the share's blocks, in item order, and
  // the header (for FinishPoint) of each point they belong to, in the order of the points.
  std::vector<PointBlock> blocks;
  std::vector<PointResult> block_headers;
  int threads = 0;
  int64_t total_trials = 0;
  double simulate_seconds = 0.0;    // wall time of trial generation and estimation
  double statistics_seconds = 0.0;  // summed time of the per-point statistics tasks, which
                                    // overlap the next point's trials
  double wall_seconds = 0.0;
};

RunResult RunExperiment(const Experiment& experiment, const RunOptions& options);

// The data point setup the runner uses for (pattern, sigma): for replaying a trial. Its `seed` is
// the point's key (KnownPointKey) and its `point` the stream word kKnownStream.
PointSetup MakePointSetup(const Experiment& experiment, const estimate::Model& model,
                          int pattern_index, int sigma_index);

}  // namespace patlab::sim

#include "patlab/sim/runner.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <span>
#include <utility>

#include "patlab/core/error.h"
#include "patlab/core/timeprofile.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/noise_prediction.h"
#include "patlab/sim/point_key.h"
#include "patlab/sim/runner_internal.h"
#include "patlab/stats/summary.h"

namespace patlab::sim {

namespace {

using estimate::Estimator;
using Clock = std::chrono::steady_clock;

using internal::BlockMoments;
using internal::Differences;
using internal::Fold;
using internal::KsAgainstFast;
using internal::PairedTest;
using internal::Samples;

}  // namespace

PointSetup MakePointSetup(const Experiment& experiment, const estimate::Model& model,
                          int pattern_index, int sigma_index) {
  PointSetup setup;
  setup.model = &model;
  setup.noise = experiment.noise;
  setup.sigma_mm = experiment.sigmas_mm[sigma_index];
  setup.field_length_mm = experiment.field_length_mm;
  setup.field_width_mm = experiment.field_width_mm;
  // The point's identity, not its grid position, keys its trials (docs/architecture.md rule 1).
  setup.seed = KnownPointKey(experiment.seed, experiment.patterns[pattern_index], experiment.noise,
                             setup.sigma_mm);
  setup.point = kKnownStream;
  for (Estimator e : experiment.estimators) setup.run[static_cast<int>(e)] = true;
  setup.ml_options = experiment.ml_options;
  // robust: the inlier per-axis std (averaged over the axes) and the outlier mixture.
  const NoiseModel& noise = experiment.noise;
  setup.robust.sigma_mm =
      setup.sigma_mm * std::sqrt((1.0 + noise.sigma_y_ratio * noise.sigma_y_ratio) / 2.0);
  setup.robust.outlier_probability = noise.outlier_probability;
  setup.robust.outlier_sigma_ratio = noise.outlier_sigma_ratio;
  const estimate::GaussianNoise gaussian = experiment.noise.GaussianPart();
  if (!gaussian.IsLeastSquares()) {
    setup.ml_weights = std::make_shared<const estimate::GaussianWeights>(
        estimate::GaussianWeights::Make(model, gaussian));
  }
  return setup;
}

namespace {

// Two sets of sample arrays: the statistics of point k (a task) run while point k + 1 is
// simulated into the other set, so neither stage waits for the other. Each point's results are
// computed by serial code into their own slot: the overlap changes timing only.
// The counters of an iterative estimator (ml, robust) over one batch of trials: its steps, its
// non-converged trials and the first of them (an index in the block, -1 if none). Integers, so
// summing the batches in order gives what summing the trials would.
struct MlBatch {
  int64_t iterations = 0, nonconverged = 0, first_nonconverged = -1;
};

struct PointBuffers {
  Samples samples[estimate::kNumEstimators];  // indexed by estimate::Estimator
  std::vector<MlBatch> ml_batches;            // one per batch of the block
  std::vector<MlBatch> robust_batches;        // the same for robust
  BatchOutput output;  // views of the sample arrays (the ML arrays are per batch)

  PointBuffers(const std::vector<Estimator>& estimators, int64_t trials) {
    for (Estimator e : estimators) {
      Samples& s = samples[static_cast<int>(e)];
      s.Resize(trials);
      output.errors[static_cast<int>(e)] = ErrorArrays{s.x.data(), s.y.data(), s.theta.data()};
    }
    ml_batches.resize(static_cast<size_t>((trials + kBatchSize - 1) / kBatchSize));
    robust_batches.resize(ml_batches.size());
  }
  PointBuffers(const PointBuffers&) = delete;
  PointBuffers& operator=(const PointBuffers&) = delete;
};

// What the statistics of every point of one pattern share.
struct PatternBounds {
  std::optional<estimate::StdPerSigma> crlb;  // NoiseCramerRaoBound
  std::array<estimate::StdPerSigma, estimate::kNumEstimators>
      predicted{};  // indexed by estimate::Estimator
};

PatternBounds BoundsOf(const estimate::Model& model, const std::vector<Estimator>& estimators,
                       const NoiseModel& noise) {
  PatternBounds bounds;
  bounds.crlb = NoiseCramerRaoBound(model, noise);
  for (Estimator e : estimators) {
    bounds.predicted[static_cast<int>(e)] = estimate::PredictedStd(model, e);
  }
  return bounds;
}

// The ML counters of a batch from its per-trial Newton steps and terminations.
MlBatch CountMl(const uint8_t* iterations, const uint8_t* termination, int count, int64_t first) {
  MlBatch m;
  for (int t = 0; t < count; ++t) {
    m.iterations += iterations[t];
    if (termination[t] != static_cast<uint8_t>(estimate::Termination::kConverged)) {
      if (m.first_nonconverged < 0) m.first_nonconverged = first + t;
      ++m.nonconverged;
    }
  }
  return m;
}

// Stage 1: trials first_trial .. first_trial + trials - 1 of a point (a block) in fixed batches
// (any thread may run any batch), each batch writing at its offset in the block's arrays and its
// ML counters to its slot of ml_batches (the per-trial ML arrays are the thread's, one batch
// long, so the block holds no per-trial array but the samples).
void RunTrials(const PointSetup& setup, int64_t first_trial, int64_t trials,
               const BatchOutput& output, std::span<MlBatch> ml_batches,
               std::span<MlBatch> robust_batches) {
  const int64_t num_batches = (trials + kBatchSize - 1) / kBatchSize;
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(0, num_batches, 1),
      [&](const tbb::blocked_range<int64_t>& range) {
        for (int64_t b = range.begin(); b != range.end(); ++b) {
          const int64_t first = b * kBatchSize;
          const int count = static_cast<int>(std::min<int64_t>(kBatchSize, trials - first));
          BatchOutput at = output;
          for (ErrorArrays& e : at.errors) {
            if (e.x_mm == nullptr) continue;
            e.x_mm += first;
            e.y_mm += first;
            e.theta_rad += first;
          }
          thread_local std::array<uint8_t, kBatchSize> ml_iterations, ml_termination,
              robust_iterations, robust_termination;
          at.ml_iterations = ml_iterations.data();
          at.ml_termination = ml_termination.data();
          at.robust_iterations = robust_iterations.data();
          at.robust_termination = robust_termination.data();
          RunBatch(setup, static_cast<uint64_t>(first_trial + first), count, at);
          if (setup.run[static_cast<int>(Estimator::kMl)]) {
            ml_batches[b] = CountMl(ml_iterations.data(), ml_termination.data(), count, first);
          }
          if (setup.run[static_cast<int>(Estimator::kRobust)]) {
            robust_batches[b] =
                CountMl(robust_iterations.data(), robust_termination.data(), count, first);
          }
        }
      },
      tbb::simple_partitioner());
}

// The bound (where the noise model has one) and the first-order prediction at the point's
// sigma. The linearised estimator's std scales with the effective per-axis patch std; the
// common-mode offset moves the position only (every estimator is translation equivariant),
// adding its variance per axis.
void FillBounds(const NoiseModel& noise, const PatternBounds& bounds, double sigma_mm,
                EstimatorResult* r) {
  if (bounds.crlb) {
    r->crlb_position_mm = bounds.crlb->position_per_axis * sigma_mm;
    r->crlb_theta_rad = bounds.crlb->theta * sigma_mm;
  } else {
    r->crlb_position_mm = r->crlb_theta_rad = std::nan("");
  }
  const estimate::StdPerSigma& pr = bounds.predicted[static_cast<int>(r->estimator)];
  const double noise_scale = noise.EffectiveSigmaRatio();
  const double g = noise.common_sigma_ratio;
  r->predicted_position_mm =
      sigma_mm * std::sqrt(std::pow(pr.position_per_axis * noise_scale, 2) + g * g);
  r->predicted_theta_rad = sigma_mm * pr.theta * noise_scale;
}

// ml or robust: non-converged trials (the first for replay, as a trial index of the point) and
// the steps of a block, from that estimator's batch counters.
void MlCounters(const std::vector<MlBatch>& batch_counters, int64_t first_trial, int64_t trials,
                EstimatorBlock* b) {
  const size_t batches = static_cast<size_t>((trials + kBatchSize - 1) / kBatchSize);
  for (size_t k = 0; k < batches; ++k) {
    const MlBatch& m = batch_counters[k];
    b->iterations += m.iterations;
    b->nonconverged += m.nonconverged;
    if (b->first_nonconverged_trial < 0 && m.first_nonconverged >= 0) {
      b->first_nonconverged_trial = first_trial + m.first_nonconverged;
    }
  }
}

// Stage 2: every estimator's block statistics, from the block's samples in `pb`; the first block
// also compares each estimator with fast (KsAgainstFast's steps). The comparisons consume the
// compared estimators' arrays; the arrays are not needed after this stage (the next block is
// simulated into them).
void BlockStatistics(const Experiment& experiment, PointBuffers& pb, double sigma_mm,
                     int64_t first_trial, int64_t trials, std::span<EstimatorBlock> out) {
  const auto& estimators = experiment.estimators;
  const auto fast_at = std::find(estimators.begin(), estimators.end(), Estimator::kFast);
  const size_t n = static_cast<size_t>(trials);
  for (size_t k = 0; k < estimators.size(); ++k) {
    if (estimators[k] == Estimator::kMl) MlCounters(pb.ml_batches, first_trial, trials, &out[k]);
    if (estimators[k] == Estimator::kRobust) {
      MlCounters(pb.robust_batches, first_trial, trials, &out[k]);
    }
  }
  const bool compare = first_trial == 0 && fast_at != estimators.end() && sigma_mm > 0.0;
  if (!compare) {
    BlockMoments(experiment, pb.samples, n, out);
    return;
  }
  const Samples& fast = pb.samples[static_cast<int>(Estimator::kFast)];
  const auto other = [&](size_t k) -> Samples& {
    return pb.samples[static_cast<int>(estimators[k])];
  };
  tbb::parallel_for(size_t{0}, estimators.size(), [&](size_t k) {
    if (estimators[k] != Estimator::kFast) KsAgainstFast(fast, other(k), n, &out[k].vs_fast);
  });
  Differences differences;
  differences.fast_index = static_cast<size_t>(fast_at - estimators.begin());
  differences.fast = &fast;
  PATLAB_CHECK(estimators.size() <= differences.other.size());
  for (size_t k = 0; k < estimators.size(); ++k) {
    if (estimators[k] != Estimator::kFast) differences.other[k] = &other(k);
  }
  const std::function<void(const stats::PlanarTile&)> visit = std::ref(differences);
  BlockMoments(experiment, pb.samples, n, out, &visit);
  tbb::parallel_for(size_t{0}, estimators.size(), [&](size_t k) {
    if (estimators[k] == Estimator::kFast) return;
    Samples& o = other(k);
    const std::span<double> scratch(o.y.data(), n);
    out[k].vs_fast.wilcoxon_position =
        PairedTest(std::span<double>(o.x.data(), n), differences.nonzero_position[k], scratch);
    out[k].vs_fast.wilcoxon_theta =
        PairedTest(std::span<double>(o.theta.data(), n), differences.nonzero_theta[k], scratch);
  });
}

// The estimator's result from its blocks, folded in trial order; `header` holds its bounds.
EstimatorResult FinishEstimator(const EstimatorResult& header, const EstimatorBlock& f) {
  EstimatorResult r = header;
  const Estimator e = r.estimator;
  const double n = static_cast<double>(f.x.n);
  r.x = SummariseMoments(f.x);
  r.y = SummariseMoments(f.y);
  r.theta = SummariseMoments(f.theta);
  r.position_std_mm = std::sqrt((r.x.std * r.x.std + r.y.std * r.y.std) / 2.0);
  const stats::StdWithCi pooled = stats::StdConfidenceInterval(r.position_std_mm, 2.0 * (n - 1.0));
  r.position_std_lower_mm = pooled.lower;
  r.position_std_upper_mm = pooled.upper;
  r.radial_rms_mm = std::sqrt(f.sum_sq / n);
  r.radial = SummariseMoments(f.radial);
  if (e == Estimator::kMl || e == Estimator::kRobust) {
    r.nonconverged = f.nonconverged;
    r.first_nonconverged_trial = f.first_nonconverged_trial;
    r.mean_iterations = static_cast<double>(f.iterations) / n;
  }
  r.vs_fast = f.vs_fast;
  return r;
}

PointResult PointHeader(const Experiment& experiment, int pattern_index, int sigma_index) {
  PointResult point;
  point.pattern_index = pattern_index;
  point.pattern = experiment.patterns[pattern_index].name;
  point.sigma_mm = experiment.sigmas_mm[sigma_index];
  point.point = static_cast<uint32_t>(pattern_index * experiment.sigmas_mm.size() + sigma_index);
  point.trials = experiment.trials;
  point.estimators.resize(experiment.estimators.size());
  const estimate::Model model = estimate::Model::FromPattern(experiment.patterns[pattern_index]);
  const PatternBounds bounds = BoundsOf(model, experiment.estimators, experiment.noise);
  for (size_t k = 0; k < experiment.estimators.size(); ++k) {
    EstimatorResult& r = point.estimators[k];
    r.estimator = experiment.estimators[k];
    FillBounds(experiment.noise, bounds, point.sigma_mm, &r);
    if (experiment.noise.HasCameraModels()) {
      // Camera jitter, correlated noise and colour-edge bias: each mechanism's first-order
      // variance (noise_prediction.h); FillBounds' formula covers independent noise only.
      const PredictedError p = PredictError(model, r.estimator, experiment.noise, point.sigma_mm,
                                            experiment.field_length_mm, experiment.field_width_mm);
      r.predicted_position_mm = p.position_mm;
      r.predicted_theta_rad = p.theta_rad;
    }
    if (r.estimator == Estimator::kRobust) {
      // Not linear in the noise (its weights depend on the residuals): no first-order value.
      r.predicted_position_mm = r.predicted_theta_rad = std::nan("");
    }
    if (r.estimator == Estimator::kMl && MlIsGeneralised(experiment.noise)) {
      // Generalised least squares: first order, its covariance is the inverse information.
      const bool gaussian = experiment.noise.IsGaussian();
      r.predicted_position_mm = gaussian ? r.crlb_position_mm : std::nan("");
      r.predicted_theta_rad = gaussian ? r.crlb_theta_rad : std::nan("");
    }
  }
  return point;
}

int64_t Nanoseconds(Clock::time_point since) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - since).count();
}

}  // namespace

ThreadLimit::ThreadLimit(const RunOptions& options)
    : threads_(options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency()),
      limit_(std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                   threads_)) {}

RunResult RunExperiment(const Experiment& experiment, const RunOptions& options) {
  PATLAB_CHECK(!experiment.patterns.empty());
  PATLAB_CHECK(!experiment.sigmas_mm.empty());
  PATLAB_CHECK(!experiment.estimators.empty());
  Validate(options);
  const auto wall_start = Clock::now();
  const ThreadLimit limit(options);

  RunResult result;
  result.threads = limit.threads();
  const int num_sigmas = static_cast<int>(experiment.sigmas_mm.size());
  const int64_t num_points = static_cast<int64_t>(experiment.patterns.size()) * num_sigmas;
  const std::vector<WorkBlock> work =
      ShareBlocks(num_points, experiment.trials, kStatisticsBlockTrials, options.shard);
  const int64_t blocks_per_point = BlocksPerPoint(experiment.trials, kStatisticsBlockTrials);
  const size_t num_estimators = experiment.estimators.size();
  std::vector<PointBlock> blocks(work.size());
  for (size_t i = 0; i < work.size(); ++i) {
    blocks[i].work = work[i];
    blocks[i].estimators.resize(num_estimators);
  }
  const int64_t buffer_trials = std::min(experiment.trials, kStatisticsBlockTrials);
  // Small blocks (fig5's 10^5 trials) keep two sets of arrays so that a block's statistics overlap
  // the next block's trials; beyond kOverlapMaxTrials one set, so that memory per trial is the
  // samples' (docs/hardening.md, "Bounded memory").
  const size_t sets = buffer_trials <= kOverlapMaxTrials ? 2 : 1;
  PointBuffers buffers[2] = {{experiment.estimators, buffer_trials},
                             {experiment.estimators, sets == 2 ? buffer_trials : 0}};
  tbb::task_group statistics[2];
  std::atomic<int64_t> statistics_ns{0};

  for (size_t index = 0; index < work.size(); ++index) {
    const WorkBlock& w = work[index];
    const int pi = static_cast<int>(w.point / num_sigmas),
              si = static_cast<int>(w.point % num_sigmas);
    PointBuffers& pb = buffers[index % sets];
    statistics[index % sets].wait();  // block index - sets is done with these arrays
    const estimate::Model model = estimate::Model::FromPattern(experiment.patterns[pi]);
    const PointSetup setup = MakePointSetup(experiment, model, pi, si);
    const auto sim_start = Clock::now();
    RunTrials(setup, w.first, w.count, pb.output, pb.ml_batches, pb.robust_batches);
    result.simulate_seconds += SecondsSince(sim_start);

    const std::span<EstimatorBlock> out(blocks[index].estimators);
    statistics[index % sets].run(
        [&experiment, &pb, &statistics_ns, out, w, sigma = setup.sigma_mm] {
          const auto stats_start = Clock::now();
          BlockStatistics(experiment, pb, sigma, w.first, w.count, out);
          statistics_ns += Nanoseconds(stats_start);
        });
    result.total_trials += w.count;
    if (options.progress) {
      options.progress(static_cast<int>(index + 1), static_cast<int>(work.size()));
    }
  }
  statistics[0].wait();
  statistics[1].wait();
  // Every point's blocks, folded in trial order (docs/architecture.md rule 2); a share that holds
  // only some blocks of a point returns them for `patlab merge` (shard.h).
  for (size_t begin = 0; begin < work.size();) {
    const WorkBlock& w = work[begin];
    const int pi = static_cast<int>(w.point / num_sigmas),
              si = static_cast<int>(w.point % num_sigmas);
    size_t end = begin;
    while (end < work.size() && work[end].point == w.point) ++end;
    const std::span<const PointBlock> point_blocks(blocks.data() + begin, end - begin);
    if (static_cast<int64_t>(end - begin) == blocks_per_point) {
      result.points.push_back(FinishPoint(PointHeader(experiment, pi, si), point_blocks));
    } else {
      result.block_headers.push_back(PointHeader(experiment, pi, si));
      result.blocks.insert(result.blocks.end(), point_blocks.begin(), point_blocks.end());
    }
    begin = end;
  }
  result.statistics_seconds = static_cast<double>(statistics_ns.load()) * 1e-9;
  result.wall_seconds = SecondsSince(wall_start);
  return result;
}

PointResult FinishPoint(const PointResult& header, std::span<const PointBlock> blocks) {
  PATLAB_CHECK(!blocks.empty());
  PointResult point = header;
  for (size_t k = 0; k < point.estimators.size(); ++k) {
    EstimatorBlock folded = blocks[0].estimators.at(k);
    for (size_t b = 1; b < blocks.size(); ++b) folded = Fold(folded, blocks[b].estimators.at(k));
    point.estimators[k] = FinishEstimator(header.estimators[k], folded);
  }
  return point;
}

int64_t BlocksPerPoint(int64_t per_point, int64_t block_size) {
  PATLAB_CHECK(per_point >= 1 && block_size >= 1);
  return (per_point + block_size - 1) / block_size;
}

std::vector<WorkBlock> ShareBlocks(int64_t points, int64_t per_point, int64_t block_size,
                                   const ShardSpec& shard) {
  const int64_t per = BlocksPerPoint(per_point, block_size);
  std::vector<WorkBlock> work;
  for (int64_t item = shard.index - 1; item < points * per; item += shard.count) {
    const int64_t block = item % per, first = block * block_size;
    work.push_back(WorkBlock{item / per, block, first, std::min(block_size, per_point - first)});
  }
  return work;
}

AxisSummary SummariseMoments(const stats::Moments& m) {
  const double nan = std::nan("");
  if (m.n < 2) return AxisSummary{m.n == 1 ? m.mean : nan, nan, nan, nan};
  const stats::StdWithCi s =
      stats::StdConfidenceInterval(m.Std(), static_cast<double>(m.n - 1), 0.95);
  return AxisSummary{m.mean, s.std, s.lower, s.upper};
}

double Efficiency(double bound, double achieved) {
  if (std::isnan(bound) || !(achieved > 0.0)) return std::nan("");
  return (bound * bound) / (achieved * achieved);
}

std::vector<OptionsProblem> Check(const RunOptions& options) {
  OptionsChecker check;
  check.Require("threads", options.threads, options.threads >= 0 && options.threads <= kMaxThreads,
                "an integer in [0, " + std::to_string(kMaxThreads) + "] (0 = all cores)");
  check.Require("shard.count", options.shard.count,
                options.shard.count >= 1 && options.shard.count <= kMaxShards,
                "an integer in [1, " + std::to_string(kMaxShards) + "]");
  check.Require("shard.index", options.shard.index,
                options.shard.index >= 1 && options.shard.index <= options.shard.count,
                "an integer in [1, shard.count]");
  return check.Take();
}

void Validate(const RunOptions& options) { ThrowFirstProblem(Check(options)); }

}  // namespace patlab::sim

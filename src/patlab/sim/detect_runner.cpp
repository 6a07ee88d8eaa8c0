#include "patlab/sim/detect_runner.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/timeprofile.h"
#include "patlab/estimate/bounds.h"
#include "patlab/sim/point_key.h"
#include "patlab/stats/summary.h"

namespace patlab::sim {

namespace {

using Clock = std::chrono::steady_clock;

// What one frame leaves in its slot.
struct FrameSlot {
  FrameScore score;
  detect::DetectStats stats;
  int false_blobs = 0, missing_patches = 0, colour_errors = 0;
};

}  // namespace

int NumDetectPoints(const Experiment& experiment) {
  return static_cast<int>(experiment.patterns.size() *
                          experiment.detect.false_blob_rates_per_m2.size() *
                          experiment.sigmas_mm.size());
}

DetectPoint MakeDetectPoint(const Experiment& experiment, uint32_t point) {
  const DetectSettings& d = experiment.detect;
  const int num_sigmas = static_cast<int>(experiment.sigmas_mm.size());
  const int num_rates = static_cast<int>(d.false_blob_rates_per_m2.size());
  PATLAB_CHECK_OP(static_cast<int>(point), <, NumDetectPoints(experiment));
  DetectPoint p;
  p.point = point;
  p.sigma_index = static_cast<int>(point) % num_sigmas;
  p.rate_index = (static_cast<int>(point) / num_sigmas) % num_rates;
  p.pattern_index = static_cast<int>(point) / num_sigmas / num_rates;
  p.sigma_mm = experiment.sigmas_mm[p.sigma_index];
  p.config = d.detector;
  p.config.patterns = {d.detector.patterns[d.detector_pattern[p.pattern_index]]};
  if (d.matched_sigma) {
    p.config.options.patch_sigma_mm = std::max(p.config.options.patch_sigma_mm,
                                               p.sigma_mm * experiment.noise.EffectiveSigmaRatio());
  }
  p.scene = d.scene;
  p.scene.pattern = 0;
  p.scene.false_blob_rate_per_m2 = d.false_blob_rates_per_m2[p.rate_index];
  p.key = DetectPointKey(experiment.seed, experiment.patterns[p.pattern_index], experiment.noise,
                         p.sigma_mm, p.scene.false_blob_rate_per_m2, p.config.patterns[0],
                         p.config.palette);
  return p;
}

Scene GenerateDetectFrame(const Experiment& experiment, const DetectPoint& point,
                          const detect::Detector& detector, uint64_t frame) {
  RandomStream rng(point.key, kDetectStream, frame);
  const NoiseModel& noise = experiment.noise;
  const double sigma = point.sigma_mm;
  const Vec2 common = noise.CommonOffset(sigma, rng);
  PatchNoise patch_noise;
  patch_noise.sigma_mm = sigma;
  if (!noise.HasCameraModels()) {  // no camera-level model: the plain models' own streams
    patch_noise.perturb = [&noise, sigma, common](const Vec2& truth, double /*radius_mm*/,
                                                  RandomStream& r) -> Vec2 {
      return truth + common + noise.PatchError(sigma, r);
    };
    return GenerateScene(detector, point.scene, patch_noise, rng);
  }
  // Camera-level models (noise.h FrameCameraNoise): the scene measures every robot's patches in
  // pattern order, so the n-th call is patch n mod (pattern size). The frame's roll and scale
  // come from their own stream, so the scene's draws are those of the same point without them.
  const Pattern& pattern = point.config.patterns.front().pattern;
  std::vector<Vec2> positions;
  int key_index = -1;
  for (int i = 0; i < pattern.size(); ++i) {
    positions.push_back(pattern.patches[i].position_mm);
    if (pattern.patches[i].role == PatchRole::kKey) key_index = i;
  }
  RandomStream camera_rng(point.key, kDetectCameraStream, frame);
  FrameCameraNoise camera(noise, positions, key_index, camera_rng);
  patch_noise.perturb = [&noise, &camera, sigma, common](const Vec2& truth, double /*radius_mm*/,
                                                         RandomStream& r) -> Vec2 {
    return camera.Next(truth + common, noise.PatchError(sigma, r));
  };
  return GenerateScene(detector, point.scene, patch_noise, rng);
}

namespace {

// Stage 1: the point's frames in parallel, each into its slot. A Detector is not thread-safe:
// one per thread, all built from the same configuration (their output does not depend on
// which). Returns the geometric tolerance the detectors applied.
double RunFrames(const Experiment& experiment, const DetectPoint& point, const WorkBlock& block,
                 std::vector<FrameSlot>* slots) {
  const double match_radius_mm = experiment.detect.match_radius_mm;
  tbb::enumerable_thread_specific<detect::Detector> detectors(
      [&point] { return detect::Detector(point.config); });
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, block.count, 16),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      detect::Detector& detector = detectors.local();
                      std::vector<detect::Detection> detections;
                      for (int64_t f = range.begin(); f != range.end(); ++f) {
                        const Scene scene = GenerateDetectFrame(
                            experiment, point, detector, static_cast<uint64_t>(block.first + f));
                        FrameSlot& slot = (*slots)[f];
                        detector.Detect(scene.blobs, &detections, &slot.stats);
                        slot.score = ScoreFrame(scene, detections, match_radius_mm);
                        slot.false_blobs = scene.num_false_blobs;
                        slot.missing_patches = scene.num_missing_patches;
                        slot.colour_errors = scene.num_colour_errors;
                      }
                    });
  return detectors.local().ResidualTolerance(0);
}

// Stage 2a: a block's counters and the moments of its pose errors, summed serially in frame order.
void SumFrames(const std::vector<FrameSlot>& slots, int64_t count, DetectBlock* b) {
  std::vector<double> ex, ey, et;
  for (int64_t f = 0; f < count; ++f) {
    const FrameSlot& slot = slots[f];
    const FrameScore& s = slot.score;
    b->robots += s.robots;
    b->correct += s.correct;
    b->wrong_id += s.wrong_id;
    b->unknown_id += s.unknown_id;
    b->ambiguous += s.ambiguous;
    b->missed += s.missed;
    b->false_positives += s.false_positives;
    b->false_blobs += slot.false_blobs;
    b->missing_patches += slot.missing_patches;
    b->colour_errors += slot.colour_errors;
    b->stats += slot.stats;
    for (const PoseError& e : s.pose_errors) {
      ex.push_back(e.dx_mm);
      ey.push_back(e.dy_mm);
      et.push_back(e.dtheta_rad);
    }
  }
  if (ex.empty()) return;
  const std::span<const double> columns[3] = {ex, ey, et};
  stats::Moments m[3];
  stats::MomentsOfEach(columns, m);
  b->x = m[0];
  b->y = m[1];
  b->theta = m[2];
}

// The point's identity, detector sigma and the bound at its sigma (isotropic noise only).
DetectPointResult PointHeader(const Experiment& experiment, const DetectPoint& point) {
  DetectPointResult r;
  r.pattern_index = point.pattern_index;
  r.pattern = experiment.patterns[point.pattern_index].name;
  r.sigma_mm = point.sigma_mm;
  r.false_blob_rate_per_m2 = point.scene.false_blob_rate_per_m2;
  r.point = point.point;
  r.frames = experiment.detect.frames;
  r.detector_sigma_mm = point.config.options.patch_sigma_mm;
  if (experiment.noise.IsIsotropicGaussian()) {
    const estimate::StdPerSigma crlb = estimate::CramerRaoBound(
        estimate::Model::FromPattern(experiment.patterns[point.pattern_index]));
    r.crlb_position_mm = crlb.position_per_axis * r.sigma_mm;
    r.crlb_theta_rad = crlb.theta * r.sigma_mm;
  } else {
    r.crlb_position_mm = r.crlb_theta_rad = std::nan("");
  }
  return r;
}

}  // namespace

DetectPointResult FinishDetectPoint(const DetectPointResult& header,
                                    std::span<const DetectBlock> blocks) {
  PATLAB_CHECK(!blocks.empty());
  DetectPointResult r = header;
  stats::Moments x, y, theta;
  for (const DetectBlock& b : blocks) {
    r.robots += b.robots;
    r.correct += b.correct;
    r.wrong_id += b.wrong_id;
    r.unknown_id += b.unknown_id;
    r.ambiguous += b.ambiguous;
    r.missed += b.missed;
    r.false_positives += b.false_positives;
    r.false_blobs += b.false_blobs;
    r.missing_patches += b.missing_patches;
    r.colour_errors += b.colour_errors;
    r.stats += b.stats;
    x = stats::CombineMoments(x, b.x);
    y = stats::CombineMoments(y, b.y);
    theta = stats::CombineMoments(theta, b.theta);
  }
  r.tolerance_mm2 = blocks.back().tolerance_mm2;
  r.x = SummariseMoments(x);
  r.y = SummariseMoments(y);
  r.theta = SummariseMoments(theta);
  // Stage 2b: the rates with their 95% intervals.
  r.detection = stats::WilsonInterval(r.correct, r.robots);
  r.wrong_id_rate = stats::WilsonInterval(r.wrong_id, r.correct + r.wrong_id);
  r.ambiguous_rate = stats::WilsonInterval(r.ambiguous, r.robots);
  r.false_positives_per_frame = stats::GarwoodInterval(r.false_positives, r.frames);
  return r;
}

DetectRunResult RunDetectExperiment(const Experiment& experiment, const RunOptions& options) {
  PATLAB_CHECK(experiment.correspondence == Correspondence::kDetect);
  PATLAB_CHECK(!experiment.patterns.empty());
  PATLAB_CHECK(!experiment.sigmas_mm.empty());
  Validate(options);
  const auto wall_start = Clock::now();
  const ThreadLimit limit(options);

  DetectRunResult result;
  result.threads = limit.threads();
  const int64_t frames = experiment.detect.frames;
  const int64_t blocks_per_point = BlocksPerPoint(frames, kStatisticsBlockFrames);
  const std::vector<WorkBlock> work =
      ShareBlocks(NumDetectPoints(experiment), frames, kStatisticsBlockFrames, options.shard);
  std::vector<FrameSlot> slots(std::min(frames, kStatisticsBlockFrames));
  std::vector<DetectBlock> blocks(work.size());
  for (size_t index = 0; index < work.size(); ++index) {
    const WorkBlock& w = work[index];
    const DetectPoint point = MakeDetectPoint(experiment, static_cast<uint32_t>(w.point));
    DetectBlock& b = blocks[index];
    b.work = w;
    const auto sim_start = Clock::now();
    b.tolerance_mm2 = RunFrames(experiment, point, w, &slots);
    result.simulate_seconds += SecondsSince(sim_start);

    const auto stats_start = Clock::now();
    SumFrames(slots, w.count, &b);
    result.statistics_seconds += SecondsSince(stats_start);
    result.total_frames += w.count;
    if (options.progress) {
      options.progress(static_cast<int>(index + 1), static_cast<int>(work.size()));
    }
  }
  // Every point's blocks, folded in frame order (docs/architecture.md rule 2); a share that holds
  // only some blocks of a point returns them for `patlab merge` (shard.h).
  const auto stats_start = Clock::now();
  for (size_t begin = 0; begin < work.size();) {
    size_t end = begin;
    while (end < work.size() && work[end].point == work[begin].point) ++end;
    const DetectPointResult header = PointHeader(
        experiment, MakeDetectPoint(experiment, static_cast<uint32_t>(work[begin].point)));
    const std::span<const DetectBlock> point_blocks(blocks.data() + begin, end - begin);
    if (static_cast<int64_t>(end - begin) == blocks_per_point) {
      result.points.push_back(FinishDetectPoint(header, point_blocks));
    } else {
      result.block_headers.push_back(header);
      result.blocks.insert(result.blocks.end(), point_blocks.begin(), point_blocks.end());
    }
    begin = end;
  }
  result.statistics_seconds += SecondsSince(stats_start);
  result.wall_seconds = SecondsSince(wall_start);
  return result;
}

}  // namespace patlab::sim

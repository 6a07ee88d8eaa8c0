#include "patlab/sim/replay.h"

#include <sstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/runner.h"

namespace patlab::sim {

namespace {

void CheckRange(const ReplayIndex& index, int64_t num_points, int64_t num_indices,
                std::string_view what) {
  if (index.point >= num_points || index.index >= num_indices) {
    throw InputError("--replay " + index.spec + " is out of range; expected POINT < " +
                     std::to_string(num_points) + " and " + std::string(what) + " < " +
                     std::to_string(num_indices));
  }
}

}  // namespace

ReplayIndex ParseReplayIndex(std::string_view spec, std::string_view what) {
  ReplayIndex r{-1, -1, std::string(spec)};
  char comma = 0;
  std::istringstream is{std::string(spec)};
  if (!(is >> r.point >> comma >> r.index) || comma != ',' || !is.eof() || r.point < 0 ||
      r.index < 0) {
    throw InputError("--replay is '" + std::string(spec) + "'; expected POINT," +
                     std::string(what) + " (two integers >= 0)");
  }
  return r;
}

TrialReplay ReplayTrial(const Experiment& experiment, const ReplayIndex& index) {
  const int64_t num_sigmas = static_cast<int64_t>(experiment.sigmas_mm.size());
  const int64_t num_points = static_cast<int64_t>(experiment.patterns.size()) * num_sigmas;
  CheckRange(index, num_points, experiment.trials, "TRIAL");
  const int pattern_index = static_cast<int>(index.point / num_sigmas);
  const int sigma_index = static_cast<int>(index.point % num_sigmas);
  TrialReplay r;
  r.point = index.point;
  r.trial = index.index;
  r.pattern = &experiment.patterns[pattern_index];
  r.seed = experiment.seed;
  const estimate::Model model = estimate::Model::FromPattern(*r.pattern);
  const PointSetup setup = MakePointSetup(experiment, model, pattern_index, sigma_index);
  r.sigma_mm = setup.sigma_mm;
  std::array<Vec2, kMaxPatches> observed;
  GenerateTrial(setup, static_cast<uint64_t>(r.trial), &r.truth, observed.data());
  r.observed.assign(observed.begin(), observed.begin() + r.pattern->size());
  r.estimators = experiment.estimators;
  const TrialOutcome outcome = RunTrialAsInBatch(setup, static_cast<uint64_t>(r.trial),
                                                 static_cast<uint64_t>(experiment.trials));
  r.estimates = outcome.estimates;
  r.errors = outcome.errors;
  r.ml_summary.iterations = outcome.ml_iterations;
  r.ml_summary.termination = outcome.ml_termination;
  r.ml_summary.initial_cost =
      estimate::SumSquaredError(model, observed.data(), estimate::Fast(model, observed.data()));
  r.ml_summary.final_cost = estimate::SumSquaredError(
      model, observed.data(), r.estimates[static_cast<size_t>(estimate::Estimator::kMl)]);
  return r;
}

// Every number of the trial in its shortest round-trip form: what the run computed, bit for bit.
std::string ReplayText(const TrialReplay& r) {
  const auto num = [](double v) { return FormatRoundTrip(v); };
  std::string out =
      StringPrintf("point %lld (pattern %s, sigma %.6g mm), trial %lld, seed %llu\n",
                   static_cast<long long>(r.point), r.pattern->name.c_str(), r.sigma_mm,
                   static_cast<long long>(r.trial), static_cast<unsigned long long>(r.seed));
  out += "truth      x " + num(r.truth.x_mm) + " mm  y " + num(r.truth.y_mm) + " mm  theta " +
         num(r.truth.theta_rad) + " rad\n";
  for (size_t i = 0; i < r.observed.size(); ++i) {
    out += StringPrintf("patch %-2d   observed (", static_cast<int>(i)) + num(r.observed[i].x()) +
           ", " + num(r.observed[i].y()) + ") mm\n";
  }
  bool ml = false;
  for (estimate::Estimator e : r.estimators) {
    const Pose2& p = r.estimates[static_cast<size_t>(e)];
    const Pose2& d = r.errors[static_cast<size_t>(e)];
    out += StringPrintf("%-6s     x ", std::string(estimate::EstimatorName(e)).c_str()) +
           num(p.x_mm) + " mm  y " + num(p.y_mm) + " mm  theta " + num(p.theta_rad) +
           " rad  (error " + num(d.x_mm) + " mm, " + num(d.y_mm) + " mm, " + num(d.theta_rad) +
           " rad)\n";
    ml = ml || e == estimate::Estimator::kMl;
  }
  if (!ml) return out;
  out += StringPrintf("ml summary %s after %d iterations, cost %.6g -> %.6g mm^2\n",
                      std::string(estimate::TerminationName(r.ml_summary.termination)).c_str(),
                      r.ml_summary.iterations, r.ml_summary.initial_cost, r.ml_summary.final_cost);
  return out;
}

FrameReplay ReplayDetectFrame(const Experiment& experiment, const ReplayIndex& index) {
  CheckRange(index, NumDetectPoints(experiment), experiment.detect.frames, "FRAME");
  const DetectPoint p = MakeDetectPoint(experiment, static_cast<uint32_t>(index.point));
  detect::Detector detector(p.config);
  FrameReplay r;
  r.point = index.point;
  r.frame = index.index;
  r.pattern = experiment.patterns[p.pattern_index].name;
  r.sigma_mm = p.sigma_mm;
  r.false_blob_rate_per_m2 = p.scene.false_blob_rate_per_m2;
  r.seed = experiment.seed;
  r.palette = p.config.palette;
  r.scene = GenerateDetectFrame(experiment, p, detector, static_cast<uint64_t>(r.frame));
  detector.Detect(r.scene.blobs, &r.detections);
  r.score = ScoreFrame(r.scene, r.detections, experiment.detect.match_radius_mm);
  return r;
}

std::string ReplayText(const FrameReplay& r) {
  std::string out = StringPrintf(
      "point %lld (pattern %s, sigma %.6g mm, false blobs %.6g /m^2), frame %lld, seed %llu\n",
      static_cast<long long>(r.point), r.pattern.c_str(), r.sigma_mm, r.false_blob_rate_per_m2,
      static_cast<long long>(r.frame), static_cast<unsigned long long>(r.seed));
  for (const SceneRobot& robot : r.scene.robots) {
    out += StringPrintf("robot      %-7s id %-3d x %.3f mm  y %.3f mm  theta %.6f rad\n",
                        r.palette[robot.team_colour].c_str(), robot.id, robot.pose.x_mm,
                        robot.pose.y_mm, robot.pose.theta_rad);
  }
  for (size_t k = 0; k < r.scene.blobs.size(); ++k) {
    const detect::Blob& b = r.scene.blobs[k];
    out +=
        StringPrintf("blob %-5zu %-7s (%.3f, %.3f) mm  area %.1f mm^2\n", k,
                     r.palette[b.colour].c_str(), b.position_mm.x(), b.position_mm.y(), b.area_mm2);
  }
  for (const detect::Detection& d : r.detections) {
    out += StringPrintf(
        "detection  %-7s id %-3d %-12s x %.3f mm  y %.3f mm  theta %.6f rad  E %.3f mm^2\n",
        r.palette[d.team_colour].c_str(), d.id,
        std::string(detect::DetectionStatusName(d.status)).c_str(), d.pose.x_mm, d.pose.y_mm,
        d.pose.theta_rad, d.residual_mm2);
  }
  const FrameScore& s = r.score;
  out += StringPrintf(
      "score      robots %d correct %d wrong_id %d unknown_id %d ambiguous %d missed %d "
      "false_positives %d\n",
      s.robots, s.correct, s.wrong_id, s.unknown_id, s.ambiguous, s.missed, s.false_positives);
  return out;
}

}  // namespace patlab::sim

// A test helper: frames of GenerateScene detected and scored one after another, summed. The
// runner (detect_runner.h) is the library's way to do this in parallel with intervals; this
// serial sum lets scene and detector tests state rates on a few hundred frames.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "patlab/detect/detector.h"
#include "patlab/sim/scene.h"

namespace patlab::sim {

struct DetectionScore {
  long frames = 0, robots = 0, correct = 0, wrong_id = 0, unknown_id = 0, ambiguous = 0, missed = 0,
       false_positives = 0;
  double sum_position_error2_mm2 = 0.0;  // over correct detections: dx^2 + dy^2
  double sum_angle_error2_rad2 = 0.0;
  detect::DetectStats stats;  // the detector's stage counters, summed

  void Add(const FrameScore& f) {
    ++frames;
    robots += f.robots;
    correct += f.correct;
    wrong_id += f.wrong_id;
    unknown_id += f.unknown_id;
    ambiguous += f.ambiguous;
    missed += f.missed;
    false_positives += f.false_positives;
    for (const PoseError& e : f.pose_errors) {
      sum_position_error2_mm2 += e.dx_mm * e.dx_mm + e.dy_mm * e.dy_mm;
      sum_angle_error2_rad2 += e.dtheta_rad * e.dtheta_rad;
    }
  }
  static double Ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }
  double detection_rate() const { return Ratio(correct, robots); }
  double wrong_id_rate() const { return Ratio(wrong_id, correct + wrong_id); }
  double false_positives_per_frame() const { return Ratio(false_positives, frames); }
  double position_rms_mm() const { return std::sqrt(Ratio(sum_position_error2_mm2, correct)); }
  double angle_rms_rad() const { return std::sqrt(Ratio(sum_angle_error2_rad2, correct)); }
};

// Frames 0 .. num_frames-1 drawn with RandomStream(seed, stream, frame), detected and scored.
inline DetectionScore EvaluateScenes(detect::Detector& detector, const SceneOptions& options,
                                     const PatchNoise& noise, uint64_t seed, uint32_t stream,
                                     int num_frames, double match_radius_mm = 45.0) {
  DetectionScore total;
  std::vector<detect::Detection> detections;
  for (int frame = 0; frame < num_frames; ++frame) {
    RandomStream rng(seed, stream, static_cast<uint64_t>(frame));
    const Scene scene = GenerateScene(detector, options, noise, rng);
    detect::DetectStats stats;
    detector.Detect(scene.blobs, &detections, &stats);
    total.stats += stats;
    total.Add(ScoreFrame(scene, detections, match_radius_mm));
  }
  return total;
}

}  // namespace patlab::sim

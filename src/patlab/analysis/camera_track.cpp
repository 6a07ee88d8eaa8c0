#include "patlab/analysis/camera_track.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include "patlab/core/error.h"
#include "patlab/core/rng.h"
#include "patlab/detect/detector.h"
#include "patlab/estimate/estimators.h"
#include "patlab/stats/effective_n.h"
#include "patlab/stats/summary.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/segment.h"

namespace patlab::analysis {

std::vector<OptionsProblem> Check(const CameraTrackOptions& o) {
  OptionsChecker check;
  check.IntegerInRange("runs", o.runs, 1, 1000)
      .IntegerInRange("frames", o.frames, 2, 100000)
      .Require("speed_mm_s", o.speed_mm_s, o.speed_mm_s > 0.0 && o.speed_mm_s <= 1000.0,
               "a number in (0, 1000] (mm/s)")
      .Require("travel_mm", o.travel_mm, o.travel_mm > 0.0 && o.travel_mm <= 10000.0,
               "a number in (0, 10000] (mm)");
  return check.Take();
}

void Validate(const CameraTrackOptions& o) { ThrowFirstProblem(Check(o)); }

namespace {

constexpr double kFramesPerSecond = 30.0;

// Per-run sums for a std about each run's own mean, pooled over runs; each slot's (patch's) per-run
// series kept for the autocorrelation (tau) of the interval.
struct Pooled {
  double m2 = 0.0;
  long n = 0, runs = 0;
  std::vector<double> run;
  std::vector<std::vector<double>> slot;      // this run's series per slot
  std::vector<std::vector<double>> segments;  // finished (run, slot) series
  void Add(double v, int s = 0) {
    run.push_back(v);
    if (slot.size() <= static_cast<size_t>(s)) slot.resize(static_cast<size_t>(s) + 1);
    slot[static_cast<size_t>(s)].push_back(v);
  }
  void EndRun() {
    for (std::vector<double>& series : slot)
      if (series.size() >= 2) segments.push_back(std::move(series));
    slot.clear();
    if (run.size() < 2) {
      run.clear();
      return;
    }
    double mean = 0.0;
    for (double v : run) mean += v;
    mean /= static_cast<double>(run.size());
    for (double v : run) m2 += (v - mean) * (v - mean);
    n += static_cast<long>(run.size());
    ++runs;
    run.clear();
  }
  stats::StdWithCi Std(double* tau) const {
    const double dof = static_cast<double>(n - runs);
    *tau = 1.0;
    if (dof < 1.0) return stats::StdConfidenceInterval(std::nan(""), 1.0);
    const std::vector<std::span<const double>> spans(segments.begin(), segments.end());
    *tau = stats::VarianceEffectiveSize(spans).tau;
    return stats::StdConfidenceInterval(std::sqrt(m2 / dof), dof / *tau);
  }
};

struct GroupSums {
  Pooled x, y, theta;
  void EndRun() {
    x.EndRun();
    y.EndRun();
    theta.EndRun();
  }
};

GroupError Summarise(const std::string& name, const GroupSums& g, bool with_theta) {
  GroupError e;
  e.group = name;
  e.samples = g.x.n;
  const stats::StdWithCi sx = g.x.Std(&e.tau_x), sy = g.y.Std(&e.tau_y);
  e.sx = sx.std, e.sx_lo = sx.lower, e.sx_hi = sx.upper;
  e.sy = sy.std, e.sy_lo = sy.lower, e.sy_hi = sy.upper;
  if (with_theta) {
    const stats::StdWithCi st = g.theta.Std(&e.tau_theta);
    e.stheta = st.std, e.stheta_lo = st.lower, e.stheta_hi = st.upper;
  } else {
    e.stheta = e.stheta_lo = e.stheta_hi = e.tau_theta = std::nan("");
  }
  return e;
}

// The window around the pattern's pixel footprint: the outline of its patches' bounding circle
// (model radius + margin) mapped to pixels, grown by 8 px (blur, demosaicing), origin and width
// even, clipped to the frame.
render::PixelWindow WindowAround(const camera::CameraModel& camera, double height_mm,
                                 const Vec2& centre_mm, double radius_mm, int width, int height) {
  double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300;
  for (int k = 0; k < 16; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 16;
    const auto p =
        camera.WorldToPixel(centre_mm + radius_mm * Vec2(std::cos(a), std::sin(a)), height_mm);
    if (!p) throw InputError("camera track: the pattern leaves the camera's view");
    lo_x = std::min(lo_x, p->x()), hi_x = std::max(hi_x, p->x());
    lo_y = std::min(lo_y, p->y()), hi_y = std::max(hi_y, p->y());
  }
  int x0 = std::max(0, static_cast<int>(std::floor(lo_x)) - 8) & ~1;
  int y0 = std::max(0, static_cast<int>(std::floor(lo_y)) - 8) & ~1;
  int x1 = std::min(width, static_cast<int>(std::ceil(hi_x)) + 9);
  int y1 = std::min(height, static_cast<int>(std::ceil(hi_y)) + 9);
  if ((x1 - x0) % 2 != 0) x1 = x1 < width ? x1 + 1 : x1 - 1;
  if (x1 - x0 < 2 || y1 - y0 < 1) throw InputError("camera track: the pattern leaves the frame");
  return {x0, y0, x1 - x0, y1 - y0};
}

// Stage 2 of a frame: each true patch's measurement (the largest region of its class whose
// centroid maps within a patch radius of the truth), its error added to its group and to `all`.
// Returns whether every patch was found.
bool MeasureFrame(const vision::Segmenter& segmenter, const camera::CameraModel& camera,
                  double height_mm, const render::PixelWindow& window, const Pattern& pattern,
                  const std::vector<int>& class_of, const Pose2& truth, std::vector<Vec2>* measured,
                  GroupSums* key, GroupSums* ids, GroupSums* all, long* missed) {
  bool complete = true;
  const Vec2 origin(window.x0, window.y0);
  for (int i = 0; i < pattern.size(); ++i) {
    const Patch& patch = pattern.patches[static_cast<size_t>(i)];
    const Vec2 true_mm = truth.Apply(patch.position_mm);
    const vision::Region* best = nullptr;
    for (const vision::Region& r : segmenter.RegionsOf(class_of[static_cast<size_t>(i)])) {
      const auto w = camera.PixelToWorld(r.centroid_px + origin, height_mm);
      if (w && (*w - true_mm).norm() < patch.radius_mm &&
          (best == nullptr || r.area_px > best->area_px)) {
        best = &r;
      }
    }
    if (best == nullptr) {
      ++*missed;
      complete = false;
      continue;
    }
    const Vec2 m = *camera.PixelToWorld(best->centroid_px + origin, height_mm);
    (*measured)[static_cast<size_t>(i)] = m;
    GroupSums* g = patch.role == PatchRole::kKey ? key : ids;
    g->x.Add(m.x() - true_mm.x(), i);
    g->y.Add(m.y() - true_mm.y(), i);
    all->x.Add(m.x() - true_mm.x(), i);
    all->y.Add(m.y() - true_mm.y(), i);
  }
  return complete;
}

// The detector on a frame's regions: every region of every class as a blob (centroid and area on
// the pattern plane); the robot's detection (status ok) nearest the truth is scored.
class DetectStage {
 public:
  DetectStage(const render::FieldScene& scene, const vision::Thresholds& thresholds,
              const camera::Calibration& calibration, const std::string& team)
      : detector_(Config(scene, thresholds, calibration, team)) {}

  void Score(const vision::Segmenter& segmenter, const camera::CameraModel& camera,
             double height_mm, const render::PixelWindow& window, int num_classes, int id,
             const Pose2& truth, GroupSums* sums, CameraTrackResult* result) {
    blobs_.clear();
    const Vec2 origin(window.x0, window.y0);
    for (int c = 0; c < num_classes; ++c) {
      for (const vision::Region& r : segmenter.RegionsOf(c)) {
        const Vec2 pixel = r.centroid_px + origin;
        const auto w = camera.PixelToWorld(pixel, height_mm);
        if (w) blobs_.push_back({*w, c, r.area_px * camera.AreaScale(pixel, height_mm)});
      }
    }
    detector_.Detect(blobs_, &detections_);
    const detect::Detection* best = nullptr;
    double best_d = 1e300;
    for (const detect::Detection& d : detections_) {
      const double dist = std::hypot(d.pose.x_mm - truth.x_mm, d.pose.y_mm - truth.y_mm);
      if (d.status == detect::DetectionStatus::kOk && dist < best_d) best = &d, best_d = dist;
    }
    if (best == nullptr || best_d > 50.0) return;
    if (best->id != id) {
      ++result->wrong_id_frames;
      return;
    }
    ++result->detected_frames;
    sums->x.Add(best->pose.x_mm - truth.x_mm);
    sums->y.Add(best->pose.y_mm - truth.y_mm);
    sums->theta.Add(WrapAngle(best->pose.theta_rad - truth.theta_rad));
  }

 private:
  // The shipped detector options, adapted to the camera as patlab detect adapts them
  // (vision::AdaptToCamera: the calibration's residual, the segmentation's edge loss).
  static detect::DetectorConfig Config(const render::FieldScene& scene,
                                       const vision::Thresholds& thresholds,
                                       const camera::Calibration& calibration,
                                       const std::string& team) {
    detect::DetectorConfig config;
    for (const vision::ColorClass& c : thresholds.classes) config.palette.push_back(c.name);
    config.patterns.push_back({scene.pattern, scene.codebook, {team}});
    vision::AdaptToCamera(config, calibration, vision::FrameDetectorOptions{}.edge_loss_px);
    return config;
  }
  detect::Detector detector_;
  std::vector<detect::Blob> blobs_;
  std::vector<detect::Detection> detections_;
};

}  // namespace

CameraTrackResult RunCameraTrack(const render::FieldScene& scene,
                                 const camera::Calibration& calibration,
                                 const vision::Thresholds& thresholds, const std::string& team,
                                 int id, const render::CameraSensorOptions& sensor,
                                 const render::CameraJitter& jitter,
                                 const CameraTrackOptions& options) {
  Validate(options);
  const auto start = std::chrono::steady_clock::now();
  render::FieldScene s = scene;
  s.options.width_px =
      calibration.image_width_px > 0 ? calibration.image_width_px : scene.options.width_px;
  s.options.height_px =
      calibration.image_height_px > 0 ? calibration.image_height_px : scene.options.height_px;
  const Pattern& pattern = s.pattern;
  const int n = pattern.size();
  std::vector<std::string> names = render::PatchColours(pattern, s.codebook, team, id);
  if (options.all_white) {
    for (const std::string& name : names) s.colours[name] = s.colours.at("white");
    for (std::string& name : names) name = "white";
  }
  std::vector<int> class_of(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    class_of[static_cast<size_t>(i)] = thresholds.Find(names[static_cast<size_t>(i)]);
    if (class_of[static_cast<size_t>(i)] < 0) {
      throw InputError("camera track: colour \"" + names[static_cast<size_t>(i)] +
                       "\" is not a class of " + thresholds.source + "; expected it there");
    }
  }
  double extent_mm = 0.0;
  for (const Patch& p : pattern.patches)
    extent_mm = std::max(extent_mm, p.position_mm.norm() + p.radius_mm);
  const double height_mm = s.options.robot_height_mm;
  const camera::CameraModel& camera = calibration.camera;
  const estimate::Model model = estimate::Model::FromPattern(pattern);
  vision::Segmenter segmenter(thresholds, vision::SegmenterOptions{});

  GroupSums key, ids, all, pose, detected;
  std::optional<DetectStage> detect_stage;
  if (options.detect) detect_stage.emplace(s, thresholds, calibration, team);
  CameraTrackResult result;
  std::vector<Vec2> measured(static_cast<size_t>(n));
  for (int run = 0; run < options.runs; ++run) {
    RandomStream rng(options.seed, kCameraTrackStream, static_cast<uint64_t>(run));
    const double offset = rng.Uniform(-100.0, 100.0);
    const double heading = rng.Uniform(-std::numbers::pi, std::numbers::pi);
    for (int f = 0; f < options.frames; ++f) {
      const Pose2 truth{-0.5 * options.travel_mm + options.speed_mm_s * f / kFramesPerSecond,
                        offset, heading};
      s.robots = {{team, id, truth}};
      const uint64_t frame = static_cast<uint64_t>(run) * options.frames + f;
      const render::PixelWindow window =
          WindowAround(camera, height_mm, Vec2(truth.x_mm, truth.y_mm), extent_mm + 10.0,
                       s.options.width_px, s.options.height_px);
      const camera::Image image =
          render::RenderCameraWindow(s, camera, sensor, frame, window, jitter);
      segmenter.Process(image);
      const bool complete =
          MeasureFrame(segmenter, camera, height_mm, window, pattern, class_of, truth, &measured,
                       &key, &ids, &all, &result.missed_patches);
      if (detect_stage) {
        detect_stage->Score(segmenter, camera, height_mm, window,
                            static_cast<int>(thresholds.classes.size()), id, truth, &detected,
                            &result);
      }
      if (options.progress)
        options.progress(run * options.frames + f + 1, options.runs * options.frames);
      if (!complete) continue;
      const Pose2 p = estimate::Fast(model, measured.data());
      pose.x.Add(p.x_mm - truth.x_mm);
      pose.y.Add(p.y_mm - truth.y_mm);
      pose.theta.Add(WrapAngle(p.theta_rad - truth.theta_rad));
      ++result.frames;
    }
    key.EndRun();
    ids.EndRun();
    all.EndRun();
    pose.EndRun();
    detected.EndRun();
  }
  result.groups = {Summarise("key", key, false), Summarise("id", ids, false),
                   Summarise("all", all, false), Summarise("pose", pose, true)};
  if (options.detect) result.groups.push_back(Summarise("detect", detected, true));
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace patlab::analysis

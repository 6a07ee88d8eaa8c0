#include "patlab/analysis/track_runner.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <span>

#include "patlab/camera/camera.h"
#include "patlab/core/error.h"
#include "patlab/core/rng.h"
#include "patlab/estimate/estimators.h"
#include "patlab/render/render.h"
#include "patlab/stats/smoothing.h"
#include "patlab/vision/segment.h"

namespace patlab::analysis {

namespace {

constexpr int kFramesPerBlock = 64;

camera::CameraModel MakeCamera(const TrackOptions& o) {
  camera::PinholeCamera p;
  p.fx_px = p.fy_px = o.camera.focal_length_px;
  p.cx_px = 0.5 * (o.camera.image_width_px - 1);
  p.cy_px = 0.5 * (o.camera.image_height_px - 1);
  // Straight down: camera x = world x, camera y = -world y, camera z = -world z (+ height).
  p.rotation = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  p.translation_mm = Eigen::Vector3d(0.0, 0.0, o.camera.height_mm);
  return camera::CameraModel::Pinhole(p);
}

vision::Thresholds PatchThresholds(const TrackOptions& o) {
  vision::Thresholds t;
  t.space = vision::ColorSpace::kRgb;
  vision::ColorClass white;
  white.name = "patch";
  const vision::ChannelRange range{o.threshold_level, 255};
  white.range = {range, range, range};
  white.min_area_px = 1;
  t.classes.push_back(white);
  t.source = "track";
  return t;
}

estimate::Model PatternModel(const TrackOptions& o) {
  return HasPattern(o) ? estimate::Model::FromPattern(o.pattern) : estimate::Model{};
}

// What measuring one frame needs: the options, the camera, the frame's identity and its jitter.
struct Frame {
  const TrackOptions* options;
  const camera::CameraModel* camera;
  int run;
  int frame;
  Vec2 jitter_px;
};

Vec2 FrameJitter(const TrackOptions& o, int run, int frame) {
  if (o.jitter_sigma_px == 0.0) return Vec2::Zero();
  RandomStream rng(o.seed, kJitterStream, (static_cast<uint64_t>(run) << 32) | uint32_t(frame));
  const double jx = rng.Normal();
  const double jy = rng.Normal();
  return Vec2(jx, jy) * o.jitter_sigma_px;
}

// Adds the frame's Gaussian intensity noise to a window whose top-left pixel is (x0, y0) in the
// frame: each pixel's noise comes from its frame coordinates, so overlapping windows agree.
void AddPixelNoise(const Frame& f, int x0, int y0, camera::Image* image) {
  const TrackOptions& o = *f.options;
  const int width = o.camera.image_width_px;
  for (int j = 0; j < image->height_px; ++j) {
    uint8_t* row = image->Row(j);
    for (int i = 0; i < image->width_px; ++i) {
      const auto pixel = static_cast<uint32_t>((y0 + j) * width + (x0 + i));
      const auto w = PhiloxBlock(o.seed, static_cast<uint32_t>(f.frame),
                                 static_cast<uint32_t>(f.run), kPixelStream, pixel);
      double z0, z1;
      BoxMuller(UniformOpen01(w[0], w[1]), UniformOpen01(w[2], w[3]), &z0, &z1);
      const long v = std::lround(row[3 * i] + o.pixel_sigma * z0);
      const auto c = static_cast<uint8_t>(std::clamp(v, 0L, 255L));
      row[3 * i] = row[3 * i + 1] = row[3 * i + 2] = c;
    }
  }
}

// Renders one disc (centre in image pixels, jitter included) in a small window of the frame,
// adds the frame's intensity noise, segments it and returns the largest region's centroid in
// image pixels.
bool MeasureWindow(const Frame& f, const Vec2& centre_px, double radius_px,
                   vision::Segmenter* segmenter, Vec2* centroid_px) {
  const TrackOptions& o = *f.options;
  const int half = static_cast<int>(std::ceil(radius_px)) + kWindowMarginPx;
  const int side = 2 * half + 1;
  const int width = o.camera.image_width_px, height = o.camera.image_height_px;
  const int x0 =
      std::clamp(static_cast<int>(std::lround(centre_px.x())) - half, 0, std::max(0, width - side));
  const int y0 = std::clamp(static_cast<int>(std::lround(centre_px.y())) - half, 0,
                            std::max(0, height - side));
  const auto level = static_cast<uint8_t>(o.patch_level);
  const auto bg = static_cast<uint8_t>(o.background_level);
  const render::Disc disc{centre_px - Vec2(x0, y0), radius_px, {level, level, level}};
  camera::Image image = render::RenderDiscs(
      side, side, {bg, bg, bg}, std::span<const render::Disc>(&disc, 1), o.supersampling);
  if (o.pixel_sigma > 0.0) AddPixelNoise(f, x0, y0, &image);
  segmenter->Process(image);
  const auto regions = segmenter->RegionsOf(0);
  if (regions.empty()) return false;
  *centroid_px = regions.front().centroid_px + Vec2(x0, y0);
  return true;
}

bool MeasureWorldDisc(const Frame& f, const Vec2& world_mm, double radius_mm,
                      vision::Segmenter* segmenter, Vec2* measured_mm) {
  const TrackOptions& o = *f.options;
  const double depth_mm = o.camera.height_mm - o.plane_height_mm;
  const auto pixel = f.camera->WorldToPixel(world_mm, o.plane_height_mm);
  PATLAB_CHECK(pixel.has_value());
  Vec2 centroid_px;
  if (!MeasureWindow(f, *pixel + f.jitter_px, radius_mm * o.camera.focal_length_px / depth_mm,
                     segmenter, &centroid_px)) {
    return false;
  }
  const auto world = f.camera->PixelToWorld(centroid_px, o.plane_height_mm);
  PATLAB_CHECK(world.has_value());
  *measured_mm = *world;
  return true;
}

// Measures subject k (a disc, or the pattern after the discs) whose true pose is `truth`.
bool MeasureSubjectInFrame(const Frame& f, const estimate::Model& model, const Pose2& truth, int k,
                           vision::Segmenter* segmenter, Pose2* measured) {
  const TrackOptions& o = *f.options;
  const int num_discs = static_cast<int>(o.diameters_mm.size());
  *measured = Pose2{0.0, 0.0, 0.0};
  if (k < num_discs) {
    Vec2 p;
    if (!MeasureWorldDisc(f, Vec2(truth.x_mm, truth.y_mm), 0.5 * o.diameters_mm[k], segmenter,
                          &p)) {
      return false;
    }
    *measured = Pose2{p.x(), p.y(), 0.0};
    return true;
  }
  std::array<Vec2, kMaxPatches> observed;
  for (int i = 0; i < o.pattern.size(); ++i) {
    const Patch& patch = o.pattern.patches[i];
    if (!MeasureWorldDisc(f, truth.Apply(patch.position_mm), patch.radius_mm, segmenter,
                          &observed[i])) {
      return false;
    }
  }
  *measured = estimate::Fast(model, observed.data());
  return true;
}

struct RawSample {
  Vec2 position_mm = Vec2::Zero();
  double theta_rad = 0.0;
  bool found = false;
};
// Every frame of every run: [subject][run][frame].
using RawSamples = std::vector<std::vector<std::vector<RawSample>>>;

// Stage 1: every frame of every run, TBB over blocks of frames, each sample in its fixed slot.
RawSamples MeasureAllFrames(const TrackOptions& o, const std::vector<RunSetup>& setups, int threads,
                            const std::function<void(int, int)>& progress) {
  const camera::CameraModel camera = MakeCamera(o);
  const vision::Thresholds thresholds = PatchThresholds(o);
  const estimate::Model model = PatternModel(o);
  const int num_subjects = NumSubjects(o);
  const int samples = o.samples_per_run;
  RawSamples raw(num_subjects,
                 std::vector<std::vector<RawSample>>(o.runs, std::vector<RawSample>(samples)));
  const int blocks_per_run = (samples + kFramesPerBlock - 1) / kFramesPerBlock;
  tbb::task_arena arena(threads);
  std::mutex progress_mutex;
  int blocks_done = 0;
  arena.execute([&] {
    tbb::parallel_for(0, o.runs * blocks_per_run, [&](int task) {
      const int run = task / blocks_per_run;
      const int begin = (task % blocks_per_run) * kFramesPerBlock;
      const int end = std::min(samples, begin + kFramesPerBlock);
      vision::Segmenter segmenter(thresholds, vision::SegmenterOptions{});
      for (int frame = begin; frame < end; ++frame) {
        const Frame f{&o, &camera, run, frame, FrameJitter(o, run, frame)};
        for (int k = 0; k < num_subjects; ++k) {
          RawSample& s = raw[k][run][frame];
          Pose2 pose;
          s.found = MeasureSubjectInFrame(f, model, TruthPose(o, setups[run], frame, k), k,
                                          &segmenter, &pose);
          s.position_mm = Vec2(pose.x_mm, pose.y_mm);
          s.theta_rad = pose.theta_rad;
        }
      }
      if (progress) {
        const std::lock_guard<std::mutex> lock(progress_mutex);
        progress(++blocks_done, o.runs * blocks_per_run);
      }
    });
  });
  return raw;
}

// Linear interpolation over missing samples (nearest valid sample beyond the ends).
void FillMissing(std::vector<double>* v, const std::vector<bool>& found) {
  const int n = static_cast<int>(v->size());
  int prev = -1;
  for (int i = 0; i < n; ++i) {
    if (!found[i]) continue;
    for (int k = prev + 1; k < i; ++k) {
      (*v)[k] =
          prev < 0 ? (*v)[i] : (*v)[prev] + ((*v)[i] - (*v)[prev]) * (k - prev) / double(i - prev);
    }
    prev = i;
  }
  for (int k = prev + 1; k < n && prev >= 0; ++k) (*v)[k] = (*v)[prev];
}

// Stage 2 for subject k in one run: the smoothing residuals (the paper's estimate, section II)
// and the true errors, both in the track frame, over the kept (trimmed, found) samples.
SubjectRun AnalyseRun(const TrackOptions& o, const std::vector<RawSample>& r, const RunSetup& setup,
                      int k) {
  const int samples = o.samples_per_run;
  const bool is_pattern = k >= static_cast<int>(o.diameters_mm.size());
  SubjectRun out;
  std::vector<bool> found(samples);
  std::vector<double> mx(samples), my(samples), mt(samples);
  for (int i = 0; i < samples; ++i) {
    found[i] = r[i].found;
    out.missed_frames += r[i].found ? 0 : 1;
    mx[i] = r[i].position_mm.x();
    my[i] = r[i].position_mm.y();
    mt[i] = r[i].theta_rad;
  }
  if (out.missed_frames == samples) return out;
  for (std::vector<double>* v : {&mx, &my, &mt}) FillMissing(v, found);
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  const std::vector<double> rx = stats::SmoothingResiduals(mx, smoothing);
  const std::vector<double> ry = stats::SmoothingResiduals(my, smoothing);
  const std::vector<double> rt =
      is_pattern ? stats::SmoothingResiduals(mt, smoothing) : std::vector<double>();
  for (int i = o.trim_samples; i < samples - o.trim_samples; ++i) {
    if (!found[i]) continue;
    const Pose2 t = TruthPose(o, setup, i, k);
    const Vec2 est = ToTrackFrame(Vec2(rx[i], ry[i]), setup.heading_rad);
    const Vec2 truth = ToTrackFrame(Vec2(mx[i] - t.x_mm, my[i] - t.y_mm), setup.heading_rad);
    out.sample.push_back(i);
    out.est_x_mm.push_back(est.x());
    out.est_y_mm.push_back(est.y());
    out.true_x_mm.push_back(truth.x());
    out.true_y_mm.push_back(truth.y());
    if (is_pattern) {
      out.est_theta_rad.push_back(rt[i]);
      out.true_theta_rad.push_back(WrapAngle(mt[i] - t.theta_rad));
    }
  }
  return out;
}

double SecondsBetween(std::chrono::steady_clock::time_point a,
                      std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

RunSetup MakeRunSetup(const TrackOptions& o, int run) {
  RandomStream rng(o.seed, kRunStream, static_cast<uint64_t>(run));
  RunSetup s;
  const double h = o.heading_max_deg * std::numbers::pi / 180.0;
  s.heading_rad = rng.Uniform(-h, h);
  // Start so that the middle of the travel passes near the image centre whatever the heading.
  const double start_x = -0.5 * TravelMm(o) + rng.Uniform(-o.start_jitter_mm, o.start_jitter_mm);
  const double start_y = rng.Uniform(-0.5 * o.lateral_range_mm, 0.5 * o.lateral_range_mm);
  s.start_mm = Vec2(start_x, start_y);
  return s;
}

Pose2 TruthPose(const TrackOptions& o, const RunSetup& setup, int frame, int subject) {
  const Vec2 dir(std::cos(setup.heading_rad), std::sin(setup.heading_rad));
  const Vec2 across(-dir.y(), dir.x());
  const Vec2 platform = setup.start_mm + dir * (o.speed_mm_per_s * frame / o.rate_hz);
  const Vec2 p = platform + across * SubjectOffsetMm(o, subject);
  return Pose2{p.x(), p.y(), setup.heading_rad};
}

Vec2 ToTrackFrame(const Vec2& e, double heading_rad) {
  const double c = std::cos(heading_rad), s = std::sin(heading_rad);
  return Vec2(c * e.x() + s * e.y(), -s * e.x() + c * e.y());
}

bool MeasureDisc(const TrackOptions& options, int run, int frame, const Vec2& world_mm,
                 double diameter_mm, Vec2* measured_mm) {
  const camera::CameraModel camera = MakeCamera(options);
  vision::Segmenter segmenter(PatchThresholds(options), vision::SegmenterOptions{});
  const Frame f{&options, &camera, run, frame, FrameJitter(options, run, frame)};
  return MeasureWorldDisc(f, world_mm, 0.5 * diameter_mm, &segmenter, measured_mm);
}

bool MeasureSubject(const TrackOptions& options, int run, int frame, int subject, Pose2* measured) {
  PATLAB_CHECK(subject >= 0 && subject < NumSubjects(options));
  const camera::CameraModel camera = MakeCamera(options);
  vision::Segmenter segmenter(PatchThresholds(options), vision::SegmenterOptions{});
  const Frame f{&options, &camera, run, frame, FrameJitter(options, run, frame)};
  return MeasureSubjectInFrame(f, PatternModel(options),
                               TruthPose(options, MakeRunSetup(options, run), frame, subject),
                               subject, &segmenter, measured);
}

std::vector<ReplayedSubject> ReplayFrame(const TrackOptions& options, int run, int frame) {
  PATLAB_CHECK(run >= 0 && run < options.runs);
  PATLAB_CHECK(frame >= 0 && frame < options.samples_per_run);
  const RunSetup setup = MakeRunSetup(options, run);
  const std::vector<std::string> names = SubjectNames(options);
  std::vector<ReplayedSubject> subjects;
  for (int k = 0; k < NumSubjects(options); ++k) {
    ReplayedSubject s;
    s.name = names[k];
    s.truth = TruthPose(options, setup, frame, k);
    s.found = MeasureSubject(options, run, frame, k, &s.measured);
    if (s.found) {
      s.true_error_mm = ToTrackFrame(
          Vec2(s.measured.x_mm - s.truth.x_mm, s.measured.y_mm - s.truth.y_mm), setup.heading_rad);
      s.has_theta = k >= static_cast<int>(options.diameters_mm.size());
      if (s.has_theta) s.true_theta_error_rad = WrapAngle(s.measured.theta_rad - s.truth.theta_rad);
    }
    subjects.push_back(s);
  }
  return subjects;
}

TrackResult RunTrack(const TrackOptions& o, const TrackRunOptions& run_options) {
  Validate(o);
  const auto start = std::chrono::steady_clock::now();
  TrackResult result;
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  result.smoothing_radius = static_cast<int>(stats::GaussianKernel(smoothing).size()) - 1;
  result.subjects = SubjectNames(o);
  for (int run = 0; run < o.runs; ++run) result.setups.push_back(MakeRunSetup(o, run));
  result.threads =
      run_options.threads > 0 ? run_options.threads : tbb::this_task_arena::max_concurrency();

  const RawSamples raw = MeasureAllFrames(o, result.setups, result.threads, run_options.progress);
  const auto measured = std::chrono::steady_clock::now();
  result.measure_seconds = SecondsBetween(start, measured);

  const int num_subjects = NumSubjects(o);
  result.data.assign(num_subjects, std::vector<SubjectRun>(o.runs));
  for (int k = 0; k < num_subjects; ++k) {
    for (int run = 0; run < o.runs; ++run) {
      result.data[k][run] = AnalyseRun(o, raw[k][run], result.setups[run], k);
    }
  }
  const auto analysed = std::chrono::steady_clock::now();
  result.analysis_seconds = SecondsBetween(measured, analysed);
  result.wall_seconds = SecondsBetween(start, analysed);
  return result;
}

}  // namespace patlab::analysis

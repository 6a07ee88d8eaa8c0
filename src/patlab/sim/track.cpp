#include "patlab/sim/track.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/rng.h"
#include "patlab/estimate/estimators.h"
#include "patlab/io/pattern_file.h"
#include "patlab/io/toml_util.h"
#include "patlab/vision/camera.h"
#include "patlab/vision/segment.h"

namespace patlab::sim {

namespace {

using io::FormatNumber;

constexpr int kWindowMarginPx = 3;  // background pixels around a disc in its render window
constexpr int kFramesPerBlock = 64;

std::string Where(const std::string& key, const std::string& table) {
  return table.empty() ? key : key + " in [" + table + "]";
}

vision::CameraModel MakeCamera(const TrackOptions& o) {
  vision::PinholeCamera p;
  p.fx_px = p.fy_px = o.camera.focal_length_px;
  p.cx_px = 0.5 * (o.camera.image_width_px - 1);
  p.cy_px = 0.5 * (o.camera.image_height_px - 1);
  // Straight down: camera x = world x, camera y = -world y, camera z = -world z (+ height).
  p.rotation = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  p.translation_mm = Eigen::Vector3d(0.0, 0.0, o.camera.height_mm);
  return vision::CameraModel::Pinhole(p);
}

bool HasPattern(const TrackOptions& o) { return !o.pattern_file.empty(); }

// Radius around the subject's origin that the subject covers (mm).
double PatternExtentMm(const Pattern& pattern) {
  double extent = 0.0;
  for (const Patch& p : pattern.patches) {
    extent = std::max(extent, p.position_mm.norm() + p.radius_mm);
  }
  return extent;
}

std::vector<double> SubjectExtentsMm(const TrackOptions& o) {
  std::vector<double> extents;
  for (double d : o.diameters_mm) extents.push_back(0.5 * d);
  if (HasPattern(o)) extents.push_back(PatternExtentMm(o.pattern));
  return extents;
}

// Across-track offset of subject k on the platform: centred, spacing_mm apart.
double SubjectOffsetMm(const TrackOptions& o, int k, int num_subjects) {
  return (k - 0.5 * (num_subjects - 1)) * o.spacing_mm;
}

double TravelMm(const TrackOptions& o) {
  return o.speed_mm_per_s * (o.samples_per_run - 1) / o.rate_hz;
}

struct Frame {
  const TrackOptions* options;
  const vision::CameraModel* camera;
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

// Renders one disc (centre in image pixels, jitter included) in a small window of the frame,
// adds the frame's intensity noise, segments it and returns the largest region's centroid in
// image pixels.
bool MeasureWindow(const Frame& f, const Vec2& centre_px, double radius_px, vision::Segmenter* segmenter,
                   Vec2* centroid_px) {
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
  const vision::Disc disc{centre_px - Vec2(x0, y0), radius_px, {level, level, level}};
  vision::Image image =
      vision::RenderDiscs(side, side, {bg, bg, bg}, std::span<const vision::Disc>(&disc, 1), o.supersampling);
  if (o.pixel_sigma > 0.0) {
    for (int j = 0; j < side; ++j) {
      uint8_t* row = image.Row(j);
      for (int i = 0; i < side; ++i) {
        const uint32_t pixel = static_cast<uint32_t>((y0 + j) * width + (x0 + i));
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
  segmenter->Process(image);
  const auto regions = segmenter->RegionsOf(0);
  if (regions.empty()) return false;
  *centroid_px = regions.front().centroid_px + Vec2(x0, y0);
  return true;
}

bool MeasureWorldDisc(const Frame& f, const Vec2& world_mm, double radius_mm, vision::Segmenter* segmenter,
                      Vec2* measured_mm) {
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

struct RawSample {
  Vec2 position_mm = Vec2::Zero();
  double theta_rad = 0.0;
  bool found = false;
};

// Linear interpolation over missing samples (nearest valid sample beyond the ends).
void FillMissing(std::vector<double>* v, const std::vector<bool>& found) {
  const int n = static_cast<int>(v->size());
  int prev = -1;
  for (int i = 0; i < n; ++i) {
    if (!found[i]) continue;
    if (prev + 1 < i) {
      for (int k = prev + 1; k < i; ++k) {
        (*v)[k] = prev < 0 ? (*v)[i]
                           : (*v)[prev] + ((*v)[i] - (*v)[prev]) * (k - prev) / double(i - prev);
      }
    }
    prev = i;
  }
  for (int k = prev + 1; k < n && prev >= 0; ++k) (*v)[k] = (*v)[prev];
}

std::string Num(double v, int digits = 6) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string Fixed(double v, int decimals) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

double MmPerPixel(const TrackOptions& o) {
  return (o.camera.height_mm - o.plane_height_mm) / o.camera.focal_length_px;
}

std::vector<TrackProblem> CheckTrackOptions(const TrackOptions& o) {
  std::vector<TrackProblem> p;
  auto add = [&](const std::string& table, const std::string& key, const std::string& what) {
    p.push_back({table, key, what});
  };
  auto num = [&](const std::string& table, const std::string& key, double v, bool ok,
                 const std::string& expected) {
    if (!ok)
      add(table, key, Where(key, table) + " is " + FormatNumber(v) + "; expected " + expected);
  };
  num("", "runs", o.runs, o.runs >= 1 && o.runs <= 1000, "an integer in 1..1000");
  if (o.diameters_mm.empty()) {
    add("", "diameters_mm", "diameters_mm is empty; expected at least one diameter (mm)");
  }
  for (size_t i = 0; i < o.diameters_mm.size(); ++i) {
    const double d = o.diameters_mm[i];
    if (!(std::isfinite(d) && d > 0.0)) {
      add("", "diameters_mm",
          "diameters_mm has " + FormatNumber(d) + "; expected diameters > 0 (mm)");
    }
    for (size_t j = 0; j < i; ++j) {
      if (o.diameters_mm[j] == d) {
        add("", "diameters_mm",
            "diameters_mm lists " + FormatNumber(d) + " twice; expected distinct diameters");
      }
    }
  }
  const std::string pl = "platform", cam = "camera", rend = "render", noise = "noise",
                    an = "analysis";
  const int min_samples = 2 * o.trim_samples + 3;
  num(pl, "samples_per_run", o.samples_per_run,
      o.samples_per_run >= min_samples && o.samples_per_run <= 1'000'000,
      "an integer in " + std::to_string(min_samples) + "..1000000 (2 trim_samples + 3 or more)");
  num(pl, "rate_hz", o.rate_hz, o.rate_hz > 0.0, "a number > 0 (frames per second)");
  num(pl, "speed_mm_per_s", o.speed_mm_per_s, o.speed_mm_per_s >= 0.0, "a number >= 0 (mm/s)");
  num(pl, "heading_max_deg", o.heading_max_deg, o.heading_max_deg >= 0 && o.heading_max_deg <= 45,
      "a number in [0, 45] (degrees)");
  num(pl, "lateral_range_mm", o.lateral_range_mm, o.lateral_range_mm >= 0.0, "a number >= 0 (mm)");
  num(pl, "start_jitter_mm", o.start_jitter_mm, o.start_jitter_mm >= 0.0, "a number >= 0 (mm)");
  num(pl, "spacing_mm", o.spacing_mm, o.spacing_mm > 0.0, "a number > 0 (mm)");
  num(cam, "height_mm", o.camera.height_mm, o.camera.height_mm > 0.0, "a number > 0 (mm)");
  num(pl, "plane_height_mm", o.plane_height_mm,
      o.plane_height_mm < o.camera.height_mm && o.plane_height_mm > -1e6,
      "a number below height_mm in [camera] (" + FormatNumber(o.camera.height_mm) + ")");
  for (int v : {o.camera.image_width_px, o.camera.image_height_px}) {
    if (v < 16 || v > 20000) {
      add(cam, "image_size_px",
          "image_size_px in [camera] has " + std::to_string(v) +
              "; expected two integers in 16..20000 (width, height)");
      break;
    }
  }
  num(cam, "focal_length_px", o.camera.focal_length_px, o.camera.focal_length_px > 0.0,
      "a number > 0 (px)");
  num(rend, "background_level", o.background_level,
      o.background_level >= 0 && o.background_level <= 255, "an integer in 0..255");
  num(rend, "patch_level", o.patch_level, o.patch_level >= 0 && o.patch_level <= 255,
      "an integer in 0..255");
  if (o.patch_level <= o.background_level) {
    add(rend, "patch_level",
        "patch_level in [render] is " + std::to_string(o.patch_level) +
            "; expected a level above background_level (" + std::to_string(o.background_level) +
            "): white patches on a darker floor");
  }
  num(rend, "threshold_level", o.threshold_level,
      o.threshold_level > o.background_level && o.threshold_level <= o.patch_level,
      "an integer in " + std::to_string(o.background_level + 1) + ".." +
          std::to_string(o.patch_level) + " (above background_level, at most patch_level)");
  num(rend, "supersampling", o.supersampling, o.supersampling >= 1 && o.supersampling <= 32,
      "an integer in 1..32");
  num(noise, "pixel_sigma", o.pixel_sigma, o.pixel_sigma >= 0.0, "a number >= 0 (grey levels)");
  num(noise, "jitter_sigma_px", o.jitter_sigma_px, o.jitter_sigma_px >= 0.0, "a number >= 0 (px)");
  num(an, "smoothing_sigma_samples", o.smoothing_sigma_samples,
      o.smoothing_sigma_samples > 0.0 && o.smoothing_sigma_samples <= 10000,
      "a number in (0, 10000] (samples)");
  num(an, "trim_samples", o.trim_samples, o.trim_samples >= 0, "an integer >= 0");
  if (!p.empty()) return p;

  // Geometry: neighbours must not touch, and every subject must stay inside the image.
  const double mm_per_px = MmPerPixel(o);
  const std::vector<double> extents = SubjectExtentsMm(o);
  for (size_t k = 1; k < extents.size(); ++k) {
    const double needed = extents[k - 1] + extents[k] + 2 * mm_per_px;
    if (!(o.spacing_mm > needed)) {
      add(pl, "spacing_mm",
          "spacing_mm in [platform] is " + FormatNumber(o.spacing_mm) + "; expected more than " +
              Num(needed, 4) + " mm so that neighbouring subjects do not touch");
      return p;
    }
  }
  const double h = o.heading_max_deg * std::numbers::pi / 180.0;
  const int n = static_cast<int>(extents.size());
  const double max_offset = std::abs(SubjectOffsetMm(o, 0, n));
  const double max_extent = *std::max_element(extents.begin(), extents.end());
  const double margin_mm = (kWindowMarginPx + 2 + 6 * o.jitter_sigma_px) * mm_per_px + max_extent;
  const double reach_x =
      0.5 * TravelMm(o) + o.start_jitter_mm + max_offset * std::sin(h) + margin_mm;
  const double reach_y =
      0.5 * o.lateral_range_mm + 0.5 * TravelMm(o) * std::sin(h) + max_offset + margin_mm;
  const double view_x = 0.5 * (o.camera.image_width_px - 1) * mm_per_px;
  const double view_y = 0.5 * (o.camera.image_height_px - 1) * mm_per_px;
  if (reach_x > view_x || reach_y > view_y) {
    add(pl, "samples_per_run",
        "the track does not fit in the image: subjects reach +-" + Num(reach_x, 5) + " x +-" +
            Num(reach_y, 5) + " mm from the image centre but the view is +-" + Num(view_x, 5) +
            " x +-" + Num(view_y, 5) +
            " mm; expected a shorter track (samples_per_run, speed_mm_per_s), a smaller "
            "lateral_range_mm, spacing_mm or heading_max_deg, or a larger image");
  }
  return p;
}

void Validate(const TrackOptions& options) {
  const auto problems = CheckTrackOptions(options);
  if (!problems.empty()) throw InputError(problems.front().message);
}

namespace {

int ReadInt(const io::TomlReader& r, std::string_view key, int fallback) {
  const auto v = r.OptionalInteger(key);
  if (!v) return fallback;
  if (*v < INT_MIN / 2 || *v > INT_MAX / 2) {
    r.Fail(key, r.Describe(key) + " is " + std::to_string(*v) + "; expected a smaller integer");
  }
  return static_cast<int>(*v);
}

const toml::table* SubTable(const io::TomlReader& r, std::string_view key) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) return nullptr;
  if (node->as_table() == nullptr) {
    r.Fail(key, std::string(key) + " is " + io::TypeName(*node) + "; expected a table [" +
                    std::string(key) + "]");
  }
  return node->as_table();
}

TrackOptions ParseTable(const toml::table& root, const std::string& path) {
  io::TomlReader r(root, path);
  r.CheckKeys({"name", "description", "seed", "runs", "diameters_mm", "pattern", "patterns_dir",
               "platform", "camera", "render", "noise", "analysis"});
  TrackOptions o;
  o.source_file = path;
  o.name = r.OptionalString("name").value_or(o.name);
  if (o.name.empty() || o.name.find('/') != std::string::npos) {
    r.Fail("name", "name is \"" + o.name + "\"; expected a non-empty file base name without '/'");
  }
  o.description = r.OptionalString("description").value_or("");
  if (const auto seed = r.OptionalInteger("seed")) {
    if (*seed < 0)
      r.Fail("seed", "seed is " + std::to_string(*seed) + "; expected an integer >= 0");
    o.seed = static_cast<uint64_t>(*seed);
  }
  o.runs = ReadInt(r, "runs", o.runs);
  if (const toml::node* node = root.get("diameters_mm")) {
    const toml::array* array = node->as_array();
    if (array == nullptr) {
      r.Fail("diameters_mm",
             "diameters_mm is " + io::TypeName(*node) + "; expected an array of diameters (mm)");
    }
    o.diameters_mm.clear();
    for (const toml::node& item : *array) {
      if (const auto* i = item.as_integer()) {
        o.diameters_mm.push_back(static_cast<double>(i->get()));
      } else if (const auto* f = item.as_floating_point()) {
        o.diameters_mm.push_back(f->get());
      } else {
        throw InputError(io::LocOf(path, item),
                         "diameters_mm contains " + io::TypeName(item) + "; expected numbers (mm)");
      }
    }
  }
  if (const auto pattern = r.OptionalString("pattern"); pattern && !pattern->empty()) {
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    const std::string dir =
        (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal();
    std::string reference = *pattern;
    if (reference.find('/') != std::string::npos || reference.ends_with(".toml")) {
      reference = (base / reference).lexically_normal().string();
    }
    try {
      o.pattern_file = io::ResolvePatternPath(reference, dir);
    } catch (const InputError& e) {
      throw InputError(r.Loc("pattern"), e.what());
    }
    o.pattern = io::LoadPatternFile(o.pattern_file);
  }
  if (const toml::table* t = SubTable(r, "platform")) {
    io::TomlReader s(*t, path, "[platform]");
    s.CheckKeys({"samples_per_run", "rate_hz", "speed_mm_per_s", "heading_max_deg",
                 "lateral_range_mm", "start_jitter_mm", "spacing_mm", "plane_height_mm"});
    o.samples_per_run = ReadInt(s, "samples_per_run", o.samples_per_run);
    o.rate_hz = s.OptionalNumber("rate_hz").value_or(o.rate_hz);
    o.speed_mm_per_s = s.OptionalNumber("speed_mm_per_s").value_or(o.speed_mm_per_s);
    o.heading_max_deg = s.OptionalNumber("heading_max_deg").value_or(o.heading_max_deg);
    o.lateral_range_mm = s.OptionalNumber("lateral_range_mm").value_or(o.lateral_range_mm);
    o.start_jitter_mm = s.OptionalNumber("start_jitter_mm").value_or(o.start_jitter_mm);
    o.spacing_mm = s.OptionalNumber("spacing_mm").value_or(o.spacing_mm);
    o.plane_height_mm = s.OptionalNumber("plane_height_mm").value_or(o.plane_height_mm);
  }
  if (const toml::table* t = SubTable(r, "camera")) {
    io::TomlReader s(*t, path, "[camera]");
    s.CheckKeys({"height_mm", "image_size_px", "focal_length_px"});
    o.camera.height_mm = s.OptionalNumber("height_mm").value_or(o.camera.height_mm);
    o.camera.focal_length_px =
        s.OptionalNumber("focal_length_px").value_or(o.camera.focal_length_px);
    if (const toml::node* node = t->get("image_size_px")) {
      const toml::array* a = node->as_array();
      if (a == nullptr || a->size() != 2 || !a->get(0)->is_integer() || !a->get(1)->is_integer()) {
        s.Fail("image_size_px",
               "image_size_px in [camera] is not two integers; expected [width, height] (px)");
      }
      auto clamp = [](int64_t v) { return static_cast<int>(std::clamp<int64_t>(v, -1, 1 << 30)); };
      o.camera.image_width_px = clamp(a->get(0)->as_integer()->get());
      o.camera.image_height_px = clamp(a->get(1)->as_integer()->get());
    }
  }
  if (const toml::table* t = SubTable(r, "render")) {
    io::TomlReader s(*t, path, "[render]");
    s.CheckKeys({"background_level", "patch_level", "threshold_level", "supersampling"});
    o.background_level = ReadInt(s, "background_level", o.background_level);
    o.patch_level = ReadInt(s, "patch_level", o.patch_level);
    o.threshold_level = ReadInt(s, "threshold_level", o.threshold_level);
    o.supersampling = ReadInt(s, "supersampling", o.supersampling);
  }
  if (const toml::table* t = SubTable(r, "noise")) {
    io::TomlReader s(*t, path, "[noise]");
    s.CheckKeys({"pixel_sigma", "jitter_sigma_px"});
    o.pixel_sigma = s.OptionalNumber("pixel_sigma").value_or(o.pixel_sigma);
    o.jitter_sigma_px = s.OptionalNumber("jitter_sigma_px").value_or(o.jitter_sigma_px);
  }
  if (const toml::table* t = SubTable(r, "analysis")) {
    io::TomlReader s(*t, path, "[analysis]");
    s.CheckKeys({"smoothing_sigma_samples", "trim_samples"});
    o.smoothing_sigma_samples =
        s.OptionalNumber("smoothing_sigma_samples").value_or(o.smoothing_sigma_samples);
    o.trim_samples = ReadInt(s, "trim_samples", o.trim_samples);
  }

  const auto problems = CheckTrackOptions(o);
  if (!problems.empty()) {
    const TrackProblem& first = problems.front();
    FileLoc loc = r.Loc(first.key);
    if (!first.table.empty()) {
      if (const toml::node* t = root.get(first.table); t && t->as_table()) {
        loc = io::TomlReader(*t->as_table(), path).Loc(first.key);
      } else {
        loc = r.TableLoc();
      }
    }
    throw InputError(loc, first.message);
  }
  return o;
}

}  // namespace

TrackOptions LoadTrackExperiment(const std::string& path) {
  return ParseTable(io::ParseTomlFile(path), path);
}

TrackOptions ParseTrackExperiment(std::string_view text, const std::string& source_name) {
  return ParseTable(io::ParseTomlText(text, source_name), source_name);
}

RunSetup MakeRunSetup(const TrackOptions& o, int run) {
  RandomStream rng(o.seed, kRunStream, static_cast<uint64_t>(run));
  RunSetup s;
  const double h = o.heading_max_deg * std::numbers::pi / 180.0;
  s.heading_rad = rng.Uniform(-h, h);
  const double start_x = -0.5 * TravelMm(o) + rng.Uniform(-o.start_jitter_mm, o.start_jitter_mm);
  const double start_y = rng.Uniform(-0.5 * o.lateral_range_mm, 0.5 * o.lateral_range_mm);
  // Start so that the middle of the travel passes near the image centre whatever the heading.
  s.start_mm = Vec2(start_x, start_y);
  return s;
}

bool MeasureDisc(const TrackOptions& options, int run, int frame, const Vec2& world_mm,
                 double diameter_mm, Vec2* measured_mm) {
  const vision::CameraModel camera = MakeCamera(options);
  vision::Segmenter segmenter(PatchThresholds(options), vision::SegmenterOptions{});
  const Frame f{&options, &camera, run, frame, FrameJitter(options, run, frame)};
  return MeasureWorldDisc(f, world_mm, 0.5 * diameter_mm, &segmenter, measured_mm);
}

int NumSubjects(const TrackOptions& o) {
  return static_cast<int>(o.diameters_mm.size()) + (HasPattern(o) ? 1 : 0);
}

Pose2 TruthPose(const TrackOptions& o, const RunSetup& setup, int frame, int subject) {
  const Vec2 dir(std::cos(setup.heading_rad), std::sin(setup.heading_rad));
  const Vec2 across(-dir.y(), dir.x());
  const Vec2 platform = setup.start_mm + dir * (o.speed_mm_per_s * frame / o.rate_hz);
  const Vec2 p = platform + across * SubjectOffsetMm(o, subject, NumSubjects(o));
  return Pose2{p.x(), p.y(), setup.heading_rad};
}

bool MeasureSubject(const TrackOptions& options, int run, int frame, int subject, Pose2* measured) {
  PATLAB_CHECK(subject >= 0 && subject < NumSubjects(options));
  const vision::CameraModel camera = MakeCamera(options);
  vision::Segmenter segmenter(PatchThresholds(options), vision::SegmenterOptions{});
  const estimate::Model model =
      HasPattern(options) ? estimate::Model::FromPattern(options.pattern) : estimate::Model{};
  const Frame f{&options, &camera, run, frame, FrameJitter(options, run, frame)};
  return MeasureSubjectInFrame(f, model,
                               TruthPose(options, MakeRunSetup(options, run), frame, subject),
                               subject, &segmenter, measured);
}

TrackResult RunTrack(const TrackOptions& o, const TrackRunOptions& run_options) {
  Validate(o);
  const auto start = std::chrono::steady_clock::now();
  const vision::CameraModel camera = MakeCamera(o);
  const vision::Thresholds thresholds = PatchThresholds(o);
  const int num_discs = static_cast<int>(o.diameters_mm.size());
  const int num_subjects = num_discs + (HasPattern(o) ? 1 : 0);
  const int samples = o.samples_per_run;
  const estimate::Model model =
      HasPattern(o) ? estimate::Model::FromPattern(o.pattern) : estimate::Model{};

  TrackResult result;
  for (double d : o.diameters_mm) result.subjects.push_back(FormatNumber(d) + "mm");
  if (HasPattern(o)) result.subjects.push_back(o.pattern.name);
  for (int run = 0; run < o.runs; ++run) result.setups.push_back(MakeRunSetup(o, run));

  // Stage 1: every frame of every run, in fixed slots [subject][run][frame].
  std::vector<std::vector<std::vector<RawSample>>> raw(
      num_subjects, std::vector<std::vector<RawSample>>(o.runs, std::vector<RawSample>(samples)));
  auto truth_pose = [&](int run, int frame, int subject) {
    return TruthPose(o, result.setups[run], frame, subject);
  };
  const int blocks_per_run = (samples + kFramesPerBlock - 1) / kFramesPerBlock;
  const int threads =
      run_options.threads > 0 ? run_options.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
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
          s.found =
              MeasureSubjectInFrame(f, model, truth_pose(run, frame, k), k, &segmenter, &pose);
          s.position_mm = Vec2(pose.x_mm, pose.y_mm);
          s.theta_rad = pose.theta_rad;
        }
      }
    });
  });

  const auto measured = std::chrono::steady_clock::now();
  result.measure_seconds = std::chrono::duration<double>(measured - start).count();

  // Stage 2: smoothing residuals and true errors in the track frame, per subject and run.
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  result.data.assign(num_subjects, std::vector<SubjectRun>(o.runs));
  for (int k = 0; k < num_subjects; ++k) {
    const bool is_pattern = k >= num_discs;
    for (int run = 0; run < o.runs; ++run) {
      const std::vector<RawSample>& r = raw[k][run];
      SubjectRun& out = result.data[k][run];
      std::vector<bool> found(samples);
      std::vector<double> mx(samples), my(samples), mt(samples);
      for (int i = 0; i < samples; ++i) {
        found[i] = r[i].found;
        out.missed_frames += r[i].found ? 0 : 1;
        mx[i] = r[i].position_mm.x();
        my[i] = r[i].position_mm.y();
        mt[i] = r[i].theta_rad;
      }
      if (out.missed_frames == samples) continue;
      FillMissing(&mx, found);
      FillMissing(&my, found);
      FillMissing(&mt, found);
      const std::vector<double> rx = stats::SmoothingResiduals(mx, smoothing);
      const std::vector<double> ry = stats::SmoothingResiduals(my, smoothing);
      const std::vector<double> rt =
          is_pattern ? stats::SmoothingResiduals(mt, smoothing) : std::vector<double>();
      const double h = result.setups[run].heading_rad, c = std::cos(h), s = std::sin(h);
      for (int i = o.trim_samples; i < samples - o.trim_samples; ++i) {
        if (!found[i]) continue;
        const Pose2 t = truth_pose(run, i, k);
        const double ex = mx[i] - t.x_mm, ey = my[i] - t.y_mm;
        out.sample.push_back(i);
        out.est_x_mm.push_back(c * rx[i] + s * ry[i]);
        out.est_y_mm.push_back(-s * rx[i] + c * ry[i]);
        out.true_x_mm.push_back(c * ex + s * ey);
        out.true_y_mm.push_back(-s * ex + c * ey);
        if (is_pattern) {
          out.est_theta_rad.push_back(rt[i]);
          out.true_theta_rad.push_back(WrapAngle(mt[i] - t.theta_rad));
        }
      }
    }
  }
  result.threads = threads;
  result.analysis_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - measured).count();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

double ResidualStdFactor(const stats::SmoothingOptions& options) {
  const double sigma = options.sigma_samples;
  const auto radius = static_cast<long>(options.truncate_sigmas * sigma + 0.5);
  if (radius == 0) return 0.0;
  double sum = 0.0, sum_sq = 0.0, w0 = 0.0;
  for (long k = -radius; k <= radius; ++k) {
    const double w = std::exp(-0.5 * static_cast<double>(k * k) / (sigma * sigma));
    sum += w;
    sum_sq += w * w;
    if (k == 0) w0 = w;
  }
  w0 /= sum;
  sum_sq /= sum * sum;
  // Var(e - w * e) = s^2 (1 - 2 w_0 + sum w_k^2) for iid e.
  return std::sqrt(1.0 - 2.0 * w0 + sum_sq);
}

std::vector<TableRow> MakeTable(const TrackResult& result) {
  std::vector<TableRow> rows;
  for (size_t k = 0; k < result.subjects.size(); ++k) {
    TableRow row;
    row.subject = result.subjects[k];
    std::vector<double> ex, ey, tx, ty, et, tt;
    for (const SubjectRun& r : result.data[k]) {
      ex.insert(ex.end(), r.est_x_mm.begin(), r.est_x_mm.end());
      ey.insert(ey.end(), r.est_y_mm.begin(), r.est_y_mm.end());
      tx.insert(tx.end(), r.true_x_mm.begin(), r.true_x_mm.end());
      ty.insert(ty.end(), r.true_y_mm.begin(), r.true_y_mm.end());
      et.insert(et.end(), r.est_theta_rad.begin(), r.est_theta_rad.end());
      tt.insert(tt.end(), r.true_theta_rad.begin(), r.true_theta_rad.end());
      row.missed_frames += r.missed_frames;
    }
    if (ex.size() < 2) {
      throw InputError("subject " + row.subject + " was found in fewer than 2 frames; expected a " +
                       "patch the segmentation can see (check the levels and the noise)");
    }
    row.est_x = stats::StdWithConfidence(ex);
    row.est_y = stats::StdWithConfidence(ey);
    row.true_x = stats::StdWithConfidence(tx);
    row.true_y = stats::StdWithConfidence(ty);
    row.true_mean_x_mm = stats::Mean(tx);
    row.true_mean_y_mm = stats::Mean(ty);
    // Mean over runs of the lag-1 autocorrelation (adjacent kept samples of one run).
    double lag_x = 0.0, lag_y = 0.0;
    int runs = 0;
    for (const SubjectRun& r : result.data[k]) {
      if (r.est_x_mm.size() < 3) continue;
      lag_x += stats::Autocorrelation(r.est_x_mm, 1);
      lag_y += stats::Autocorrelation(r.est_y_mm, 1);
      ++runs;
    }
    row.est_lag1_x = runs > 0 ? lag_x / runs : 0.0;
    row.est_lag1_y = runs > 0 ? lag_y / runs : 0.0;
    if (!et.empty()) {
      row.has_theta = true;
      row.est_theta = stats::StdWithConfidence(et);
      row.true_theta = stats::StdWithConfidence(tt);
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<SizeTest> MakeSizeTests(const TrackResult& result) {
  std::vector<SizeTest> tests;
  const size_t num_discs = std::count_if(result.subjects.begin(), result.subjects.end(),
                                         [](const std::string& s) { return s.ends_with("mm"); });
  for (const char* error : {"est", "true"}) {
    const bool est = std::string(error) == "est";
    for (const char* axis : {"x", "y", "xy"}) {
      for (size_t a = 0; a < num_discs; ++a) {
        for (size_t b = a + 1; b < num_discs; ++b) {
          std::vector<double> va, vb;
          for (size_t run = 0; run < result.data[a].size(); ++run) {
            const SubjectRun& ra = result.data[a][run];
            const SubjectRun& rb = result.data[b][run];
            auto value = [&](const SubjectRun& r, size_t i) {
              const double x = est ? r.est_x_mm[i] : r.true_x_mm[i];
              const double y = est ? r.est_y_mm[i] : r.true_y_mm[i];
              const std::string ax = axis;
              return ax == "x" ? std::abs(x) : ax == "y" ? std::abs(y) : std::hypot(x, y);
            };
            // Pair the samples of the same frame (both kept).
            size_t i = 0, j = 0;
            while (i < ra.sample.size() && j < rb.sample.size()) {
              if (ra.sample[i] < rb.sample[j]) {
                ++i;
              } else if (rb.sample[j] < ra.sample[i]) {
                ++j;
              } else {
                va.push_back(value(ra, i++));
                vb.push_back(value(rb, j++));
              }
            }
          }
          SizeTest t;
          t.error = error;
          t.axis = axis;
          t.a = result.subjects[a];
          t.b = result.subjects[b];
          if (va.empty()) continue;
          auto median = [](std::vector<double> v) {
            std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
            return v[v.size() / 2];
          };
          t.median_abs_a_mm = median(va);
          t.median_abs_b_mm = median(vb);
          stats::WilcoxonOptions options;
          options.method = stats::WilcoxonMethod::kApprox;
          t.result = stats::WilcoxonSignedRank(va, vb, options);
          tests.push_back(t);
        }
      }
    }
  }
  return tests;
}

std::string TableCsv(const std::vector<TableRow>& rows) {
  std::string csv =
      "subject,n,est_sx_mm,est_sx_lo,est_sx_hi,est_sy_mm,est_sy_lo,est_sy_hi,true_sx_mm,"
      "true_sx_lo,true_sx_hi,true_sy_mm,true_sy_lo,true_sy_hi,est_over_true_x,est_over_true_y,"
      "true_mean_x_mm,true_mean_y_mm,est_lag1_x,est_lag1_y,est_stheta_rad,true_stheta_rad,"
      "missed_frames\n";
  for (const TableRow& r : rows) {
    auto ci = [](const stats::StdWithCi& s) {
      return Fixed(s.std, 4) + "," + Fixed(s.lower, 4) + "," + Fixed(s.upper, 4);
    };
    csv += r.subject + "," + std::to_string(r.est_x.n) + "," + ci(r.est_x) + "," + ci(r.est_y) +
           "," + ci(r.true_x) + "," + ci(r.true_y) + "," + Fixed(r.est_x.std / r.true_x.std, 3) +
           "," + Fixed(r.est_y.std / r.true_y.std, 3) + "," + Fixed(r.true_mean_x_mm, 4) + "," +
           Fixed(r.true_mean_y_mm, 4) + "," + Fixed(r.est_lag1_x, 3) + "," +
           Fixed(r.est_lag1_y, 3) + "," + (r.has_theta ? Num(r.est_theta.std, 4) : "") + "," +
           (r.has_theta ? Num(r.true_theta.std, 4) : "") + "," + std::to_string(r.missed_frames) +
           "\n";
  }
  return csv;
}

std::string SizeTestsCsv(const std::vector<SizeTest>& tests) {
  std::string csv =
      "error,axis,a,b,n,median_abs_a_mm,median_abs_b_mm,r_plus,r_minus,z,p_value,smaller\n";
  for (const SizeTest& t : tests) {
    const auto& w = t.result;
    // R+ > R-: |a| - |b| tends to be positive, so b has the smaller errors.
    const std::string smaller = w.r_plus > w.r_minus ? t.b : w.r_plus < w.r_minus ? t.a : "";
    csv += t.error + "," + t.axis + "," + t.a + "," + t.b + "," + std::to_string(w.n) + "," +
           Fixed(t.median_abs_a_mm, 4) + "," + Fixed(t.median_abs_b_mm, 4) + "," +
           Num(w.r_plus, 12) + "," + Num(w.r_minus, 12) + "," + Fixed(w.z, 3) + "," +
           Num(w.p_value, 3) + "," + smaller + "\n";
  }
  return csv;
}

std::string ErrorsCsv(const TrackOptions& options, const TrackResult& result, int decimate) {
  PATLAB_CHECK(decimate >= 1);
  std::string csv =
      "subject,run,frame,t_s,est_x_mm,est_y_mm,true_x_mm,true_y_mm,est_theta_rad,"
      "true_theta_rad\n";
  char buf[256];
  for (size_t k = 0; k < result.subjects.size(); ++k) {
    for (size_t run = 0; run < result.data[k].size(); ++run) {
      const SubjectRun& r = result.data[k][run];
      for (size_t i = 0; i < r.sample.size(); ++i) {
        // Every decimate-th sample and its successor: adjacent pairs survive for Fig. 6.
        const size_t phase = i % static_cast<size_t>(decimate);
        if (phase > 1) continue;
        std::snprintf(buf, sizeof buf, "%s,%zu,%d,%.4f,%.4f,%.4f,%.4f,%.4f,",
                      result.subjects[k].c_str(), run, r.sample[i], r.sample[i] / options.rate_hz,
                      r.est_x_mm[i], r.est_y_mm[i], r.true_x_mm[i], r.true_y_mm[i]);
        csv += buf;
        if (!r.est_theta_rad.empty()) {
          std::snprintf(buf, sizeof buf, "%.6f,%.6f", r.est_theta_rad[i], r.true_theta_rad[i]);
          csv += buf;
        } else {
          csv += ",";
        }
        csv += "\n";
      }
    }
  }
  return csv;
}

}  // namespace patlab::sim

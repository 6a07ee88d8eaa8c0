#include "patlab/render/scene_render.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/gaussian.h"
#include "patlab/core/rng.h"
#include "patlab/io/csv.h"
#include "patlab/render/field_render.h"

namespace patlab::render {

namespace {

// The noise stream of RandomStream(seed, stream, pixel index); any fixed value would do.
constexpr uint32_t kNoiseStream = 0;
// The blur kernel is cut at this many sigma and renormalised (scipy.ndimage's truncate = 4).
constexpr double kBlurTruncateSigmas = 4.0;

const Rgb& ColourOf(const FieldScene& scene, const std::string& name) {
  const auto it = scene.colours.find(name);
  if (it == scene.colours.end()) {
    throw InputError("colour \"" + name + "\" has no RGB; expected the scene's colours to list it");
  }
  return it->second;
}

// Moves a point of the plane at height `from` to the plane at height `to` along the camera's ray
// through it, so it is seen at the same pixel. Central projection between parallel planes is a
// homothety about the camera centre's foot point with ratio (c_z - to) / (c_z - from): a disc
// stays a disc, its radius scales by the same ratio, and lens distortion (a function of the ray
// alone) is unchanged. This draws the ball and the robot tops in one pass on one plane.
struct PlaneTransfer {
  Vec2 centre_mm;  // the camera centre's (x, y)
  double ratio = 1.0;
  Vec2 Apply(const Vec2& p_mm) const { return centre_mm + ratio * (p_mm - centre_mm); }
};

// The camera centre C = -R^T t in world coordinates (mm).
Eigen::Vector3d CameraCentre(const camera::PinholeCamera& c) {
  return -c.rotation.transpose() * c.translation_mm;
}

PlaneTransfer TransferBetweenPlanes(const camera::PinholeCamera& c, double from_mm, double to_mm) {
  const Eigen::Vector3d centre = CameraCentre(c);
  return {Vec2(centre.x(), centre.y()), (centre.z() - to_mm) / (centre.z() - from_mm)};
}

// Every disc of the scene on the plane of the pattern tops, in paint order: the ball (lowest),
// then per robot its top cover and its patches.
std::vector<Disc> SceneDiscs(const FieldScene& scene, const camera::CameraModel& camera) {
  const RenderOptions& o = scene.options;
  std::vector<Disc> discs;
  if (scene.ball_mm) {
    const PlaneTransfer t =
        TransferBetweenPlanes(camera.pinhole(), o.ball_radius_mm, o.robot_height_mm);
    discs.push_back(
        {t.Apply(*scene.ball_mm), t.ratio * o.ball_radius_mm, ColourOf(scene, scene.ball_colour)});
  }
  for (const RobotPlacement& robot : scene.robots) {
    const std::vector<std::string> names =
        PatchColours(scene.pattern, scene.codebook, robot.team, robot.id);
    if (o.robot_radius_mm > 0.0) {
      discs.push_back(
          {Vec2(robot.pose.x_mm, robot.pose.y_mm), o.robot_radius_mm, ColourOf(scene, "body")});
    }
    for (int i = 0; i < scene.pattern.size(); ++i) {
      const Patch& patch = scene.pattern.patches[static_cast<size_t>(i)];
      Disc d{robot.pose.Apply(patch.position_mm), patch.BoundingRadius(),
             ColourOf(scene, names[static_cast<size_t>(i)])};
      if (patch.shape == PatchShape::kRectangle) {
        d.half_size = 0.5 * patch.size_mm;
        d.angle_rad = robot.pose.theta_rad + patch.angle_rad;
      }
      discs.push_back(d);
    }
  }
  return discs;
}

// The blur's taps k = -radius..radius, from the one Gaussian kernel (core/gaussian.h).
std::vector<double> GaussianKernel(double sigma_px) {
  const std::vector<double> half = GaussianHalfKernel(sigma_px, kBlurTruncateSigmas);
  const size_t radius = half.size() - 1;
  std::vector<double> kernel(2 * radius + 1);
  for (size_t k = 0; k <= radius; ++k) kernel[radius + k] = kernel[radius - k] = half[k];
  return kernel;
}

// Index i reflected into [0, n) about the edges, edge sample included (d c b a | a b c d).
int Reflect(int i, int n) {
  while (i < 0 || i >= n) i = i < 0 ? -i - 1 : 2 * n - i - 1;
  return i;
}

// One pass of the separable blur, along rows (along_x) or columns, on interleaved RGB levels.
// `out` is resized, not reallocated when it already has the size (a frame's buffers are reused:
// fresh 10 MB buffers cost more in page faults than the blur itself).
void BlurPass(const std::vector<double>& in, int width, int height,
              const std::vector<double>& kernel, bool along_x, std::vector<double>& out) {
  const int radius = static_cast<int>(kernel.size() / 2);
  out.resize(in.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double sum[3] = {0.0, 0.0, 0.0};
      for (int k = -radius; k <= radius; ++k) {
        const int sx = along_x ? Reflect(x + k, width) : x;
        const int sy = along_x ? y : Reflect(y + k, height);
        const double* p = &in[3 * (static_cast<size_t>(sy) * width + sx)];
        const double w = kernel[static_cast<size_t>(k + radius)];
        for (int c = 0; c < 3; ++c) sum[c] += w * p[c];
      }
      double* q = &out[3 * (static_cast<size_t>(y) * width + x)];
      for (int c = 0; c < 3; ++c) q[c] = sum[c];
    }
  }
}

// Stages 2 and 3: blur, noise keyed by (seed, pixel), rounding to 8 bits.
void BlurAndNoise(const RenderOptions& o, camera::Image* image) {
  thread_local std::vector<double> level, across;
  level.assign(image->data.begin(), image->data.end());
  if (o.blur_sigma_px > 0.0) {
    const std::vector<double> kernel = GaussianKernel(o.blur_sigma_px);
    BlurPass(level, image->width_px, image->height_px, kernel, true, across);
    BlurPass(across, image->width_px, image->height_px, kernel, false, level);
  }
  const size_t pixels = static_cast<size_t>(image->width_px) * image->height_px;
  if (o.noise_sigma_levels == 0.0) {  // the same bytes as adding 0 x a normal, without drawing
    for (size_t i = 0; i < 3 * pixels; ++i) {
      image->data[i] = static_cast<uint8_t>(std::clamp(std::lround(level[i]), 0L, 255L));
    }
    return;
  }
  for (size_t p = 0; p < pixels; ++p) {
    RandomStream rng(o.seed, kNoiseStream, p);
    for (size_t c = 0; c < 3; ++c) {
      const double noisy = level[3 * p + c] + o.noise_sigma_levels * rng.Normal();
      image->data[3 * p + c] = static_cast<uint8_t>(std::clamp(std::lround(noisy), 0L, 255L));
    }
  }
}

}  // namespace

std::vector<OptionsProblem> Check(const RenderOptions& o) {
  OptionsChecker check;
  check.IntegerInRange("width_px", o.width_px, 1, 8192)
      .IntegerInRange("height_px", o.height_px, 1, 8192)
      .IntegerInRange("supersampling", o.supersampling, 1, 16)
      .InRange("robot_height_mm", o.robot_height_mm, 0.0, 1000.0, "mm")
      .InRange("robot_radius_mm", o.robot_radius_mm, 0.0, 500.0, "mm")
      .Require("ball_radius_mm", o.ball_radius_mm,
               o.ball_radius_mm > 0.0 && o.ball_radius_mm <= 500.0, "a number in (0, 500] (mm)")
      .InRange("blur_sigma_px", o.blur_sigma_px, 0.0, 10.0, "px")
      .InRange("noise_sigma_levels", o.noise_sigma_levels, 0.0, 64.0, "8-bit levels");
  return check.Take();
}

void Validate(const RenderOptions& options) { ThrowFirstProblem(Check(options)); }

std::vector<std::string> PatchColours(const Pattern& pattern, const detect::Codebook& codebook,
                                      const std::string& team, int id) {
  const auto entry = std::find_if(codebook.entries.begin(), codebook.entries.end(),
                                  [id](const detect::CodebookEntry& e) { return e.id == id; });
  if (entry == codebook.entries.end()) {
    throw InputError("id " + std::to_string(id) + " is not in the codebook of pattern \"" +
                     pattern.name + "\"; expected one of its " +
                     std::to_string(codebook.entries.size()) + " IDs");
  }
  const std::vector<int> slots = detect::IdSlots(pattern);
  std::vector<std::string> names;
  for (int i = 0; i < pattern.size(); ++i) {
    const Patch& patch = pattern.patches[static_cast<size_t>(i)];
    if (patch.role == PatchRole::kKey) {
      names.push_back(team);
    } else if (patch.role == PatchRole::kFixed) {
      names.push_back(patch.colour);
    } else {
      const auto slot = std::find(slots.begin(), slots.end(), i) - slots.begin();
      names.push_back(codebook.colours[static_cast<size_t>(entry->colour[slot])]);
    }
  }
  return names;
}

camera::Image RenderScene(const FieldScene& scene, const camera::CameraModel& camera) {
  const RenderOptions& o = scene.options;
  Validate(o);
  if (!camera.is_pinhole()) {
    throw InputError("the camera is a homography; expected a pinhole camera to render with");
  }
  const double camera_height_mm = CameraCentre(camera.pinhole()).z();
  if (!(camera_height_mm > std::max(o.robot_height_mm, o.ball_radius_mm))) {
    throw InputError("the camera centre is at height " + FormatNumber(camera_height_mm) +
                     " mm; expected it above the robot tops and the ball");
  }
  const std::vector<Disc> discs = SceneDiscs(scene, camera);
  // Stage 1: geometry, every disc tested on the plane of the pattern tops.
  const Rgb carpet = ColourOf(scene, "field");
  camera::Image image = RenderWorldDiscs(o.width_px, o.height_px, camera, o.robot_height_mm, carpet,
                                         discs, o.supersampling);
  if (scene.field) {  // the lines show where no disc covers the carpet
    FieldLineStyle style;
    style.carpet = carpet;
    const camera::Image lines =
        RenderFieldLines(*scene.field, camera, o.width_px, o.height_px, style);
    for (size_t i = 0; i + 2 < image.data.size(); i += 3) {
      if (std::equal(carpet.begin(), carpet.end(), image.data.begin() + static_cast<long>(i))) {
        std::copy_n(lines.data.begin() + static_cast<long>(i), 3,
                    image.data.begin() + static_cast<long>(i));
      }
    }
  }
  BlurAndNoise(o, &image);  // stages 2 and 3
  return image;
}

std::string TruthCsv(const FieldScene& scene) {
  std::string csv = "team,id,x_mm,y_mm,theta_rad\n";
  for (const RobotPlacement& r : scene.robots) {
    io::CsvWriter(&csv)
        .Cell(r.team)
        .Cell(static_cast<int64_t>(r.id))
        .Cells({FormatRoundTrip(r.pose.x_mm), FormatRoundTrip(r.pose.y_mm),
                FormatRoundTrip(r.pose.theta_rad)})
        .EndRow();
  }
  return csv;
}

// ---------------------------------------------------------------------------------------------
// Scene files.

}  // namespace patlab::render

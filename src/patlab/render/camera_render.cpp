#include "patlab/render/camera_render.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "patlab/core/error.h"
#include "patlab/core/rng.h"

namespace patlab::render {

std::vector<OptionsProblem> Check(const CameraSensorOptions& o) {
  OptionsChecker check;
  check
      .Require("exposure_gain", o.exposure_gain, o.exposure_gain > 0.0 && o.exposure_gain <= 16.0,
               "a number in (0, 16]")
      .InRange("read_noise_levels", o.read_noise_levels, 0.0, 64.0, "8-bit levels")
      .InRange("shot_noise_gain", o.shot_noise_gain, 0.0, 4.0, "levels");
  return check.Take();
}

void Validate(const CameraSensorOptions& o) { ThrowFirstProblem(Check(o)); }

std::vector<OptionsProblem> Check(const CameraJitter& j) {
  OptionsChecker check;
  check.InRange("roll_sigma_rad", j.roll_sigma_rad, 0.0, 0.1, "rad")
      .InRange("height_sigma_mm", j.height_sigma_mm, 0.0, 1000.0, "mm")
      .InRange("shift_sigma_mm", j.shift_sigma_mm, 0.0, 1000.0, "mm");
  return check.Take();
}

void Validate(const CameraJitter& j) { ThrowFirstProblem(Check(j)); }

camera::PinholeCamera JitterCamera(const camera::PinholeCamera& camera, const CameraJitter& jitter,
                                   uint64_t frame_index) {
  Validate(jitter);
  if (jitter.IsStill()) return camera;
  RandomStream rng(jitter.seed, kJitterStream, frame_index);
  const double phi = jitter.roll_sigma_rad * rng.Normal();
  const double dh = jitter.height_sigma_mm * rng.Normal();
  const double dx = jitter.shift_sigma_mm * rng.Normal();
  const double dy = jitter.shift_sigma_mm * rng.Normal();
  const Eigen::Vector3d centre = -camera.rotation.transpose() * camera.translation_mm;
  camera::PinholeCamera out = camera;
  out.rotation =
      Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ()).toRotationMatrix() * camera.rotation;
  out.translation_mm = -out.rotation * (centre + Eigen::Vector3d(dx, dy, dh));
  return out;
}

namespace {

// RGGB: channel of photosite (x, y) (x, y in whole-frame coordinates; windows start even).
inline int BayerChannel(int x, int y) {
  return (y & 1) == 0 ? ((x & 1) == 0 ? 0 : 1) : ((x & 1) == 0 ? 1 : 2);
}

inline uint8_t Quantise(double v) {
  return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// Standard normals of every photosite of one row, from its Philox block (x, y, frame,
// kCameraStream): plane k of `z` (width values each) holds normal k, k < per_pixel <= 3, from two
// Box-Muller pairs of one-word uniforms. Each stage is a plain loop the compiler vectorises
// (rng.h PhiloxBatch; cos and sin in separate loops, docs/architecture.md "Numbers that matter").
struct RowNoise {
  std::vector<uint32_t> words;
  std::vector<double> radius, angle, z;
  void Draw(uint64_t seed, int x0, int width, uint32_t y, uint32_t frame, int per_pixel) {
    const size_t n = static_cast<size_t>(width);
    words.resize(5 * n);
    radius.resize(n);
    angle.resize(n);
    z.resize(3 * n);
    uint32_t* c0 = words.data();
    for (size_t i = 0; i < n; ++i) c0[i] = static_cast<uint32_t>(x0) + static_cast<uint32_t>(i);
    PhiloxBatch(seed, c0, y, frame, kCameraStream, width, c0 + n, c0 + 2 * n, c0 + 3 * n,
                c0 + 4 * n);
    for (int pair = 0; pair < (per_pixel + 1) / 2; ++pair) {
      const uint32_t* u1 = c0 + (1 + 2 * pair) * n;
      const uint32_t* u2 = u1 + n;
      for (size_t i = 0; i < n; ++i) radius[i] = std::sqrt(-2.0 * std::log(UniformOpen01(u1[i])));
      for (size_t i = 0; i < n; ++i) angle[i] = 2.0 * std::numbers::pi * UniformOpen01(u2[i]);
      double* za = z.data() + 2 * pair * n;
      for (size_t i = 0; i < n; ++i) za[i] = radius[i] * std::cos(angle[i]);
      if (2 * pair + 1 < per_pixel) {
        double* zb = za + n;
        for (size_t i = 0; i < n; ++i) zb[i] = radius[i] * std::sin(angle[i]);
      }
    }
  }
};

// Stage 1-2: exposure, the mosaic (or every channel), noise, quantisation. `raw` holds 3 values
// per pixel; with the mosaic only the photosite's channel is meaningful. (ox, oy): the image's
// origin in the whole frame.
void Expose(const camera::Image& rgb, const CameraSensorOptions& s, uint64_t frame, int ox, int oy,
            std::vector<uint8_t>* raw) {
  const int w = rgb.width_px, h = rgb.height_px;
  raw->assign(static_cast<size_t>(w) * h * 3, 0);
  const bool noisy = s.read_noise_levels > 0.0 || s.shot_noise_gain > 0.0;
  const double read2 = s.read_noise_levels * s.read_noise_levels;
  const double gain = s.exposure_gain;
  RowNoise noise;
  for (int y = 0; y < h; ++y) {
    const int fy = oy + y;
    const uint8_t* in = rgb.Row(y);
    uint8_t* out = raw->data() + static_cast<size_t>(y) * w * 3;
    if (noisy) {
      noise.Draw(s.seed, ox, w, static_cast<uint32_t>(fy), static_cast<uint32_t>(frame),
                 s.bayer ? 1 : 3);
    }
    const double* z = noise.z.data();
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (s.bayer && c != BayerChannel(ox + x, fy)) continue;
        const double signal = std::min(255.0, gain * in[3 * x + c]);
        double v = signal;
        if (noisy) {
          // The photosite's one normal with the mosaic, one per channel without it.
          const size_t plane = s.bayer ? 0 : static_cast<size_t>(c);
          v += std::sqrt(read2 + s.shot_noise_gain * signal) * z[plane * w + x];
        }
        out[3 * x + c] = Quantise(v);
      }
    }
  }
}

// Stage 3: bilinear demosaicing of the RGGB mosaic in place: each missing channel is the mean of
// the nearest photosites of that colour (green at R/B: the 4 edge neighbours; R/B at G: the 2
// neighbours in the row or the column; B at R and R at B: the 4 diagonals), rounded half up.
// The mosaic is copied into one plane with a reflected border of one pixel (-1 -> 1, w -> w - 2:
// reflection keeps the Bayer phase), so the inner loop has no edge cases.
void Demosaic(int w, int h, int ox, int oy, std::vector<uint8_t>* raw) {
  const int pw = w + 2;
  std::vector<uint8_t> m(static_cast<size_t>(pw) * (h + 2));
  auto reflect = [](int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); };
  for (int y = -1; y <= h; ++y) {
    const int sy = reflect(y, h);
    uint8_t* row = m.data() + static_cast<size_t>(y + 1) * pw;
    for (int x = -1; x <= w; ++x) {
      const int sx = reflect(x, w);
      row[x + 1] = (*raw)[(static_cast<size_t>(sy) * w + sx) * 3 + BayerChannel(ox + sx, oy + sy)];
    }
  }
  for (int y = 0; y < h; ++y) {
    const uint8_t* up = m.data() + static_cast<size_t>(y) * pw + 1;
    const uint8_t* mid = up + pw;
    const uint8_t* down = mid + pw;
    uint8_t* px = raw->data() + static_cast<size_t>(y) * w * 3;
    const bool red_row = ((oy + y) & 1) == 0;
    for (int x = 0; x < w; ++x, px += 3) {
      const int own = mid[x];
      const int cross = (mid[x - 1] + mid[x + 1] + up[x] + down[x] + 2) / 4;
      const int diagonal = (up[x - 1] + up[x + 1] + down[x - 1] + down[x + 1] + 2) / 4;
      const int across = (mid[x - 1] + mid[x + 1] + 1) / 2;
      const int vertical = (up[x] + down[x] + 1) / 2;
      const bool even_x = ((ox + x) & 1) == 0;
      int r, g, b;
      if (red_row) {
        if (even_x) {  // R site
          r = own, g = cross, b = diagonal;
        } else {  // G site in an R row: R left and right, B above and below
          r = across, g = own, b = vertical;
        }
      } else if (even_x) {  // G site in a B row: B left and right, R above and below
        r = vertical, g = own, b = across;
      } else {  // B site
        r = diagonal, g = cross, b = own;
      }
      px[0] = static_cast<uint8_t>(r);
      px[1] = static_cast<uint8_t>(g);
      px[2] = static_cast<uint8_t>(b);
    }
  }
}

void CheckWindowOrigin(int x0, int y0) {
  if (x0 % 2 != 0 || y0 % 2 != 0) {
    throw InputError("window origin is (" + std::to_string(x0) + ", " + std::to_string(y0) +
                     "); expected even coordinates (Bayer phase, UYVY pixel pairs)");
  }
}

}  // namespace

camera::Image SimulateSensor(const camera::Image& radiance_rgb, const CameraSensorOptions& sensor,
                             uint64_t frame_index, int origin_x, int origin_y) {
  Validate(sensor);
  PATLAB_CHECK(radiance_rgb.format == camera::PixelFormat::kRgb8);
  PATLAB_CHECK(frame_index < (uint64_t{1} << 32));
  CheckWindowOrigin(origin_x, origin_y);
  const int w = radiance_rgb.width_px, h = radiance_rgb.height_px;
  if (sensor.chroma_422 && w % 2 != 0) {
    throw InputError("image width_px is " + std::to_string(w) +
                     "; expected an even width for UYVY");
  }
  std::vector<uint8_t> raw;
  Expose(radiance_rgb, sensor, frame_index, origin_x, origin_y, &raw);
  if (sensor.bayer) Demosaic(w, h, origin_x, origin_y, &raw);
  camera::Image rgb = camera::Image::Rgb(w, h);
  rgb.data = std::move(raw);
  return sensor.chroma_422 ? camera::ToUyvy(rgb) : rgb;
}

camera::Image RenderCameraWindow(const FieldScene& scene, const camera::CameraModel& camera,
                                 const CameraSensorOptions& sensor, uint64_t frame_index,
                                 const PixelWindow& window, const CameraJitter& jitter) {
  if (!camera.is_pinhole()) {
    throw InputError("the camera is a homography; expected a pinhole camera to render with");
  }
  Validate(sensor);
  Validate(jitter);
  CheckWindowOrigin(window.x0, window.y0);
  const RenderOptions& o = scene.options;
  if (window.x0 < 0 || window.y0 < 0 || window.width < 2 || window.height < 1 ||
      window.x0 + window.width > o.width_px || window.y0 + window.height > o.height_px) {
    throw InputError("window (" + std::to_string(window.x0) + ", " + std::to_string(window.y0) +
                     ") " + std::to_string(window.width) + "x" + std::to_string(window.height) +
                     " px; expected it inside the " + std::to_string(o.width_px) + "x" +
                     std::to_string(o.height_px) + " frame");
  }
  camera::PinholeCamera pinhole = JitterCamera(camera.pinhole(), jitter, frame_index);
  pinhole.cx_px -= window.x0;
  pinhole.cy_px -= window.y0;
  FieldScene quiet = scene;
  quiet.options.noise_sigma_levels = 0.0;
  quiet.options.width_px = window.width;
  quiet.options.height_px = window.height;
  return SimulateSensor(RenderScene(quiet, camera::CameraModel::Pinhole(pinhole)), sensor,
                        frame_index, window.x0, window.y0);
}

camera::Image RenderCameraFrame(const FieldScene& scene, const camera::CameraModel& camera,
                                const CameraSensorOptions& sensor, uint64_t frame_index,
                                const CameraJitter& jitter) {
  return RenderCameraWindow(scene, camera, sensor, frame_index,
                            {0, 0, scene.options.width_px, scene.options.height_px}, jitter);
}

}  // namespace patlab::render

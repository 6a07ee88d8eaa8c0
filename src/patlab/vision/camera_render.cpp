#include "patlab/vision/camera_render.h"

#include <algorithm>
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/rng.h"

namespace patlab::vision {

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

namespace {

// RGGB: channel of photosite (x, y).
inline int BayerChannel(int x, int y) {
  return (y & 1) == 0 ? ((x & 1) == 0 ? 0 : 1) : ((x & 1) == 0 ? 1 : 2);
}

inline int Reflect(int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); }

// Stage 1-2: exposure, the mosaic (or every channel), noise, quantisation. `raw` holds 3 values
// per pixel; with the mosaic only the photosite's channel is meaningful.
void Expose(const Image& rgb, const CameraSensorOptions& s, uint64_t frame,
            std::vector<uint8_t>* raw) {
  const int w = rgb.width_px, h = rgb.height_px;
  raw->assign(static_cast<size_t>(w) * h * 3, 0);
  for (int y = 0; y < h; ++y) {
    RandomStream rng(s.seed, kCameraStream, (frame << 16) + static_cast<uint64_t>(y));
    const uint8_t* in = rgb.Row(y);
    uint8_t* out = raw->data() + static_cast<size_t>(y) * w * 3;
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (s.bayer && c != BayerChannel(x, y)) continue;
        const double signal = std::min(255.0, s.exposure_gain * in[3 * x + c]);
        const double sd =
            std::sqrt(s.read_noise_levels * s.read_noise_levels + s.shot_noise_gain * signal);
        const double v = sd > 0.0 ? signal + sd * rng.Normal() : signal;
        out[3 * x + c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      }
    }
  }
}

// Stage 3: bilinear demosaicing of the RGGB mosaic in place (missing channels from the mean of
// the nearest photosites of that colour: 2 or 4 neighbours).
void Demosaic(int w, int h, std::vector<uint8_t>* raw) {
  const std::vector<uint8_t> mosaic = *raw;
  auto at = [&](int x, int y, int c) {
    return static_cast<int>(
        mosaic[(static_cast<size_t>(Reflect(y, h)) * w + Reflect(x, w)) * 3 + c]);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int own = BayerChannel(x, y);
      uint8_t* px = raw->data() + (static_cast<size_t>(y) * w + x) * 3;
      for (int c = 0; c < 3; ++c) {
        if (c == own) continue;
        int sum = 0, count = 0;
        if (c == 1) {  // green at an R or B site: the 4 edge neighbours
          sum = at(x - 1, y, 1) + at(x + 1, y, 1) + at(x, y - 1, 1) + at(x, y + 1, 1);
          count = 4;
        } else if (own == 1) {  // R or B at a G site: the 2 neighbours in the row or the column
          const bool in_row = BayerChannel(Reflect(x + 1, w), y) == c;
          sum = in_row ? at(x - 1, y, c) + at(x + 1, y, c) : at(x, y - 1, c) + at(x, y + 1, c);
          count = 2;
        } else {  // B at R or R at B: the 4 diagonal neighbours
          sum =
              at(x - 1, y - 1, c) + at(x + 1, y - 1, c) + at(x - 1, y + 1, c) + at(x + 1, y + 1, c);
          count = 4;
        }
        px[c] = static_cast<uint8_t>((sum + count / 2) / count);
      }
    }
  }
}

}  // namespace

Image SimulateSensor(const Image& radiance_rgb, const CameraSensorOptions& sensor,
                     uint64_t frame_index) {
  Validate(sensor);
  PATLAB_CHECK(radiance_rgb.format == PixelFormat::kRgb8);
  const int w = radiance_rgb.width_px, h = radiance_rgb.height_px;
  if (w % 2 != 0) {
    throw InputError("image width_px is " + std::to_string(w) +
                     "; expected an even width for UYVY");
  }
  std::vector<uint8_t> raw;
  Expose(radiance_rgb, sensor, frame_index, &raw);
  if (sensor.bayer) Demosaic(w, h, &raw);
  Image rgb = Image::Rgb(w, h);
  rgb.data = std::move(raw);
  return ToUyvy(rgb);
}

Image RenderCameraFrame(const FieldScene& scene, const CameraModel& camera,
                        const CameraSensorOptions& sensor, uint64_t frame_index) {
  FieldScene quiet = scene;
  quiet.options.noise_sigma_levels = 0.0;
  return SimulateSensor(RenderScene(quiet, camera), sensor, frame_index);
}

}  // namespace patlab::vision

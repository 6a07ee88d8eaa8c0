// A colour camera on top of the scene renderer (scene_render.h): the frames a real SSL camera
// would deliver, so the unchanged real-frame pipeline (colour thresholds, regions, calibration,
// detector) can be run on rendered robots at known poses, and each camera effect switched on
// alone. What it adds, in order, after RenderScene has drawn the scene's colours through the
// camera model (perspective, lens distortion) and the optics blur, without its own noise:
//  1. exposure: every channel times exposure_gain (1 = the scene file's colours), clipped at 255
//     at the sensor;
//  2. Bayer sensor: each photosite keeps one channel of an RGGB mosaic (row 0: R G R G ..., row 1:
//     G B G B ...), with Gaussian read noise of read_noise_levels and shot noise of variance
//     shot_noise_gain x signal (8-bit levels), rounded and clamped to 0..255;
//  3. demosaicing: bilinear, each missing channel the mean of its nearest 2 or 4 photosites of
//     that colour (edges reflected);
//  4. YUV 4:2:2: BT.601 (image.h RgbToYuv), U and V averaged over each pixel pair, packed UYVY as
//     the camera delivers it (image.h PixelFormat::kUyvy). Chroma at half horizontal resolution
//     moves colour edges along the rows: the colour-edge bias of sim/noise.h.
// Deterministic per frame identity: row y of frame f draws from RandomStream(seed, kCameraStream,
// f * 65536 + y) (core/rng.h), so frame f is the same image in any order or thread.
#pragma once

#include <cstdint>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/vision/camera.h"
#include "patlab/vision/image.h"
#include "patlab/vision/scene_render.h"

namespace patlab::vision {

inline constexpr uint32_t kCameraStream = 0x43414d;  // "CAM"

struct CameraSensorOptions {
  // Linear gain on the scene's colours, in (0, 16]; 1 = as the scene file gives them. Higher
  // exposures clip bright patches (white, yellow) at 255 and shift their thresholded hue.
  double exposure_gain = 1.0;
  // Gaussian read noise per photosite (8-bit levels), in [0, 64]; 0 = none.
  double read_noise_levels = 2.0;
  // Shot noise: variance per level of signal, in [0, 4]; a photosite of value s gets std
  // sqrt(shot_noise_gain s). 0 = none; about 0.1 for a small CCD at 8 bits.
  double shot_noise_gain = 0.05;
  // The RGGB mosaic and bilinear demosaicing; false = a three-chip camera (every channel at
  // every pixel, the noise still per channel).
  bool bayer = true;
  // Seed of the sensor noise (see above).
  uint64_t seed = 1;
};
// Every broken constraint, one per field (core/options.h).
std::vector<OptionsProblem> Check(const CameraSensorOptions& options);
void Validate(const CameraSensorOptions& options);

// Frame `frame_index` of `scene` through `camera` and the sensor: a UYVY image (width even;
// an odd scene width is an InputError). scene.options.noise_sigma_levels is ignored (the sensor
// brings its own noise); everything else of the scene's options applies.
Image RenderCameraFrame(const FieldScene& scene, const CameraModel& camera,
                        const CameraSensorOptions& sensor, uint64_t frame_index);

// Stages 1-4 on an already rendered noise-free RGB image (exposed for tests and for other
// renderers): returns the UYVY frame.
Image SimulateSensor(const Image& radiance_rgb, const CameraSensorOptions& sensor,
                     uint64_t frame_index);

}  // namespace patlab::vision

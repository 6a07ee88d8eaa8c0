// A colour camera on top of the scene renderer (scene_render.h): the frames a real SSL camera
// would deliver, so the unchanged real-frame pipeline (colour thresholds, regions, calibration,
// detector) can be run on rendered robots at known poses, and each camera effect switched on
// alone. What it adds, in order:
//  0. camera jitter (CameraJitter): per frame, the camera's pose is perturbed before the scene
//     is drawn: a roll about its optical axis, a change of its height, a shift of its centre
//     along the floor (the blob-level models of sim/noise.h, rotation and scale jitter, as the
//     camera really moves);
//  then RenderScene draws the scene's colours through the (jittered) camera model (perspective,
//  lens distortion) and the optics blur, without its own noise, and the sensor adds
//  1. exposure: every channel times exposure_gain (1 = the scene file's colours), clipped at 255
//     at the sensor;
//  2. Bayer sensor: each photosite keeps one channel of an RGGB mosaic (row 0: R G R G ..., row 1:
//     G B G B ...), with Gaussian read noise of read_noise_levels and shot noise of variance
//     shot_noise_gain x signal (8-bit levels), rounded and clamped to 0..255;
//  3. demosaicing: bilinear, each missing channel the mean of its nearest 2 or 4 photosites of
//     that colour (edges reflected);
//  4. YUV 4:2:2: BT.601 (image.h RgbToYuv), U and V averaged over each pixel pair, packed UYVY as
//     the camera delivers it (image.h PixelFormat::kUyvy). Chroma at half horizontal resolution
//     moves colour edges along the rows: the colour-edge bias of sim/noise.h. chroma_422 = false
//     returns the demosaiced RGB instead (a camera with full-resolution colour).
// Deterministic per frame identity: the noise of photosite (x, y) of frame f is a pure function
// of (seed, f, x, y) (Philox block (x, y, f, kCameraStream), core/rng.h), and the jitter of frame
// f of (jitter seed, f): frame f is the same image in any order or thread, and a window of a
// frame (RenderCameraWindow) holds exactly the pixels of the whole frame there.
#pragma once

#include <cstdint>
#include <vector>

#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/core/options.h"
#include "patlab/render/scene_render.h"

namespace patlab::render {

inline constexpr uint32_t kCameraStream = 0x43414d;  // "CAM"
inline constexpr uint32_t kJitterStream = 0x4a4954;  // "JIT"

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
  // YUV 4:2:2 (UYVY) output; false = the demosaiced RGB (full-resolution chroma).
  bool chroma_422 = true;
  // Seed of the sensor noise (see above).
  uint64_t seed = 1;
};
// Every broken constraint, one per field (core/options.h).
std::vector<OptionsProblem> Check(const CameraSensorOptions& options);
void Validate(const CameraSensorOptions& options);

// Per-frame perturbation of the camera's pose (all 0 = a still camera). Each is a Gaussian of
// the given std drawn once per frame from RandomStream(seed, kJitterStream, frame), in the order
// roll, height, shift x, shift y.
struct CameraJitter {
  // Roll about the optical axis (rad), in [0, 0.1]. At 3 m a roll phi moves a point r mm from
  // the image centre by phi r across the radius: the rotation jitter of sim/noise.h.
  double roll_sigma_rad = 0.0;
  // Change of the camera centre's height (mm), in [0, 1000]. A change dh at height h scales the
  // image by about -dh / h about the foot of the camera: the scale jitter of sim/noise.h.
  double height_sigma_mm = 0.0;
  // Shift of the camera centre along the floor, per axis (mm), in [0, 1000]: moves every point
  // of the robots' plane by about the same amount (common-mode translation jitter).
  double shift_sigma_mm = 0.0;
  uint64_t seed = 1;
  bool IsStill() const {
    return roll_sigma_rad == 0.0 && height_sigma_mm == 0.0 && shift_sigma_mm == 0.0;
  }
};
std::vector<OptionsProblem> Check(const CameraJitter& jitter);
void Validate(const CameraJitter& jitter);

// `camera` with frame `frame_index`'s jitter: roll R' = Rz(phi) R (about the camera's own z
// axis, the optical axis), centre C' = C + (dx, dy, dh), translation t' = -R' C'. A still jitter
// returns the camera unchanged.
camera::PinholeCamera JitterCamera(const camera::PinholeCamera& camera, const CameraJitter& jitter,
                                   uint64_t frame_index);

// A rectangle of the frame (px): columns x0 .. x0 + width - 1, rows y0 .. y0 + height - 1. x0,
// y0 and width must be even (Bayer phase and UYVY pixel pairs).
struct PixelWindow {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

// Frame `frame_index` of `scene` through `camera` (jittered per frame), and the sensor: a UYVY
// image (RGB when chroma_422 is false; width even: an odd scene width is an InputError).
// scene.options.noise_sigma_levels is ignored (the sensor brings its own noise); everything else
// of the scene's options applies.
camera::Image RenderCameraFrame(const FieldScene& scene, const camera::CameraModel& camera,
                                const CameraSensorOptions& sensor, uint64_t frame_index,
                                const CameraJitter& jitter = {});

// The same frame rendered only inside `window` (which must lie inside the scene's image): the
// camera's principal point moves by (-x0, -y0) and the noise keeps the whole frame's pixel
// coordinates, so the result is the whole frame's pixels there, except within a few pixels of
// the window's border when something other than flat background reaches it (the blur and the
// demosaicing reflect at the window's edges, not at the frame's). Costs the window's area, not
// the frame's: what makes a track of thousands of frames take seconds.
camera::Image RenderCameraWindow(const FieldScene& scene, const camera::CameraModel& camera,
                                 const CameraSensorOptions& sensor, uint64_t frame_index,
                                 const PixelWindow& window, const CameraJitter& jitter = {});

// Stages 1-4 on an already rendered noise-free RGB image (exposed for tests and for other
// renderers): returns the UYVY frame (RGB when chroma_422 is false). (origin_x, origin_y), both
// even, is the image's top-left pixel in the whole frame (a window's x0, y0), for the noise keys.
camera::Image SimulateSensor(const camera::Image& radiance_rgb, const CameraSensorOptions& sensor,
                             uint64_t frame_index, int origin_x = 0, int origin_y = 0);

}  // namespace patlab::render

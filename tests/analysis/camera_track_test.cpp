// The track through the colour camera (analysis/camera_track.h) on the camera-noise inputs: every
// patch found in every frame, the same numbers on a second run (frame identity), and an analytic
// check of the pixel-grid error: with a still, noise-free three-chip camera a patch's centroid
// error is at most half a pixel (4.17 mm/px / 2 = 2.1 mm) per axis, and its std over a track well
// below the uniform rounding std of a pixel, 4.17 / sqrt(12) = 1.2 mm.
#include "patlab/analysis/camera_track.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"

#include <gtest/gtest.h>

#include "../expect_error.h"

namespace patlab::analysis {
namespace {

const std::string kDir = std::string(PATLAB_SOURCE_DIR) + "/experiments/camera-noise/";

CameraTrackResult RunTrack(bool still_and_quiet, int frames) {
  const formats::SceneFile file = formats::LoadSceneFile(kDir + "track-scene.toml");
  render::CameraSensorOptions sensor;
  render::CameraJitter jitter;
  if (still_and_quiet) {
    sensor.read_noise_levels = sensor.shot_noise_gain = 0.0;
    sensor.bayer = sensor.chroma_422 = false;
  } else {
    jitter.roll_sigma_rad = 0.001;
  }
  CameraTrackOptions options;
  options.runs = 2;
  options.frames = frames;
  return RunCameraTrack(file.scene, file.calibration,
                        formats::LoadThresholds(kDir + "track.thresholds.toml"), "blue", 3, sensor,
                        jitter, options);
}

TEST(CameraTrack, EveryPatchFoundWithinThePixelGrid) {
  const CameraTrackResult r = RunTrack(true, 120);
  EXPECT_EQ(r.missed_patches, 0);
  EXPECT_EQ(r.frames, 240);
  ASSERT_EQ(r.groups.size(), 4u);
  for (const GroupError& g : r.groups) {
    SCOPED_TRACE(g.group);
    EXPECT_GT(g.sx, 0.0);
    EXPECT_LT(g.sx, 4.17 / std::sqrt(12.0));
    EXPECT_LT(g.sy, 4.17 / std::sqrt(12.0));
    EXPECT_LE(g.sx_lo, g.sx);
    EXPECT_GE(g.sx_hi, g.sx);
  }
  EXPECT_EQ(r.groups[0].samples, 240);      // the key, once per frame
  EXPECT_EQ(r.groups[1].samples, 4 * 240);  // four ID dots
}

TEST(CameraTrack, SameInputsSameNumbers) {
  const CameraTrackResult a = RunTrack(false, 40), b = RunTrack(false, 40);
  for (size_t k = 0; k < a.groups.size(); ++k) {
    EXPECT_EQ(a.groups[k].sx, b.groups[k].sx);
    EXPECT_EQ(a.groups[k].sy, b.groups[k].sy);
  }
  EXPECT_EQ(a.groups[3].stheta, b.groups[3].stheta);
}

TEST(CameraTrack, OptionsAreChecked) {
  CameraTrackOptions o;
  o.frames = 1;
  EXPECT_INPUT_ERROR(Validate(o), "frames is 1; expected an integer in [2, 100000]");
}

}  // namespace
}  // namespace patlab::analysis

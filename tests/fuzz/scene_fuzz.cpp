// Scene files of patlab render (vision/scene_render.h); relative paths resolve against the
// golden frame's folder, so seeds can name its calibration and settings.
#include "fuzz_util.h"
#include "patlab/vision/scene_render.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::vision::ParseSceneFile(patlab::fuzz::Text(data, size), "fuzz.toml",
                                         PATLAB_SOURCE_DIR "/tests/data/golden");
  });
  return 0;
}

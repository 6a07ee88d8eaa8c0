// Scene files of patlab render (formats/scene_file.h); relative paths resolve against the
// golden frame's folder, so seeds can name its calibration and settings.
#include "fuzz_util.h"
#include "patlab/formats/scene_file.h"
#include "patlab/render/scene_render.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::formats::ParseSceneFile(patlab::fuzz::Text(data, size), "fuzz.toml",
                                          PATLAB_SOURCE_DIR "/tests/data/golden");
  });
  return 0;
}

// Detector settings (formats/detector_settings.h); relative pattern and codebook paths resolve
// against the shipped experiments/ folder, so seeds can name the shipped patterns.
#include "fuzz_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::formats::ParseDetectorSettings(patlab::fuzz::Text(data, size), "fuzz.toml",
                                                 PATLAB_SOURCE_DIR "/experiments");
  });
  return 0;
}

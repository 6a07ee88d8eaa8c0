// Track experiment files (formats/track_file.h).
#include "fuzz_util.h"
#include "patlab/formats/track_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::formats::ParseTrackExperiment(patlab::fuzz::Text(data, size),
                                                PATLAB_SOURCE_DIR "/experiments/fuzz.toml");
  });
  return 0;
}

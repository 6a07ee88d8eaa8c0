// Camera calibrations (vision/camera.h).
#include "fuzz_util.h"
#include "patlab/vision/camera.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly(
      [&] { (void)patlab::vision::ParseCalibration(patlab::fuzz::Text(data, size), "fuzz.toml"); });
  return 0;
}

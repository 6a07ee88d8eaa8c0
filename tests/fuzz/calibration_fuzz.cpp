// Camera calibration files (formats/calibration_file.h).
#include "fuzz_util.h"
#include "patlab/camera/camera.h"
#include "patlab/formats/calibration_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::formats::ParseCalibration(patlab::fuzz::Text(data, size), "fuzz.toml");
  });
  return 0;
}

// Colour thresholds (formats/thresholds_file.h): CMVision colors.txt and the TOML form, as
// LoadThresholds chooses between them (a first section [Colors] is colors.txt).
#include "fuzz_util.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/color_lut.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    if (text.find("[Colors]") != std::string::npos) {
      (void)patlab::formats::ParseCmvisionColors(text, "colors.txt");
    } else {
      (void)patlab::formats::ParseThresholdsToml(text, "fuzz.toml");
    }
  });
  return 0;
}

// Image readers (vision/frame_io.h): PNG, JPEG and binary PPM chosen by their magic numbers as
// ReadFrame chooses, so one corpus reaches all three decoders.
#include <vector>

#include "fuzz_util.h"
#include "patlab/vision/frame_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    if (size >= 4 && data[0] == 0x89 && data[1] == 'P') {
      (void)patlab::vision::DecodePng(bytes, "fuzz.png");
    } else if (size >= 3 && data[0] == 0xff && data[1] == 0xd8) {
      (void)patlab::vision::DecodeJpeg(bytes, "fuzz.jpg");
    } else {
      (void)patlab::vision::DecodePpm(bytes, "fuzz.ppm");
    }
  });
  return 0;
}

// Labels files of `patlab thresholds` (formats/labels_file.h): the parser, then the pixels the
// labels name on a small image (points, rectangles and their bounds checks; no mask).
#include "fuzz_util.h"
#include "patlab/formats/labels_file.h"
#include "patlab/vision/thresholds_fit.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    const patlab::vision::Labels labels = patlab::formats::ParseLabels(text, "fuzz.toml", "");
    (void)patlab::vision::LabelPixels(labels, 64, 48, nullptr);
  });
  return 0;
}

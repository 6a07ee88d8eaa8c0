// Field models (formats/field_file.h): the lines, circles and points of a field that
// `patlab calibrate` fits to.
#include "fuzz_util.h"
#include "patlab/formats/field_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly([&] { (void)patlab::formats::ParseField(text, "fuzz.toml"); });
  return 0;
}

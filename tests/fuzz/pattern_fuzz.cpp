// Pattern files (formats/pattern_file.h).
#include "fuzz_util.h"
#include "patlab/formats/pattern_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  patlab::fuzz::ExpectInputErrorOnly(
      [&] { (void)patlab::formats::ParsePattern(patlab::fuzz::Text(data, size), "fuzz.toml"); });
  return 0;
}

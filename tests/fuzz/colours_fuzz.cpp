// The colour vocabulary (io/colour_vocabulary.h): the colour names teams use, their aliases and
// typical values, read by `patlab thresholds --auto --colours FILE`; the seed is the shipped file.
#include "fuzz_util.h"
#include "patlab/io/colour_vocabulary.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly(
      [&] { (void)patlab::io::ParseColourVocabulary(text, "fuzz.toml"); });
  return 0;
}

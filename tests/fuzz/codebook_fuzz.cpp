// Codebooks (formats/codebook_file.h) for the shipped SSL standard pattern.
#include "fuzz_util.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/codebook_file.h"
#include "patlab/formats/pattern_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const patlab::Pattern pattern =
      patlab::formats::LoadPatternFile(PATLAB_SOURCE_DIR "/patterns/ssl-standard.toml");
  static const patlab::detect::Symmetry symmetry = patlab::detect::FindSymmetry(pattern, 10.0);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    (void)patlab::formats::ParseCodebook(patlab::fuzz::Text(data, size), "fuzz.codebook.toml",
                                         pattern, symmetry);
  });
  return 0;
}

// Number columns (formats/numeric_column.h): the first byte chooses plain (even) or CSV column "x".
#include <sstream>

#include "fuzz_util.h"
#include "patlab/formats/numeric_column.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  patlab::formats::NumericColumnOptions options;
  if (data[0] % 2 == 1) options.column = "x";
  std::istringstream in(patlab::fuzz::Text(data + 1, size - 1));
  patlab::fuzz::ExpectInputErrorOnly(
      [&] { (void)patlab::formats::ParseNumericColumn(in, "fuzz.csv", options); });
  return 0;
}

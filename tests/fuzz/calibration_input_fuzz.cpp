// Calibration-input files of `patlab calibrate` (formats/calibration_input.h): the parser, with the
// field and pattern files it names resolved against PATLAB_FUZZ_WORK_DIR/run/ (beside the links
// patterns -> patterns/ and experiments -> experiments/, tests/fuzz/CMakeLists.txt), then the
// camera fit itself on what parsed, with few iterations: degenerate observations (too few,
// collinear, all at one pixel) must be refused as InputError, never crash the solver.
#include <algorithm>

#include "fuzz_util.h"
#include "patlab/calib/calibrate.h"
#include "patlab/formats/calibration_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    patlab::calib::CalibrationInput input =
        patlab::formats::ParseCalibrationInput(text, "fuzz.toml", PATLAB_FUZZ_WORK_DIR "/run");
    input.options.max_iterations = std::min(input.options.max_iterations, 20);
    (void)patlab::calib::FitCamera(input);
  });
  return 0;
}

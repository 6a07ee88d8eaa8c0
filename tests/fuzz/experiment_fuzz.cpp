// Experiment files (formats/experiment_file.h) and the noise and settings files they name. The
// loader reads a path, so each input is written to a file in PATLAB_FUZZ_WORK_DIR/run/, beside the
// links patterns -> the shipped patterns/ and experiments -> experiments/ (tests/fuzz/
// CMakeLists.txt): the seeds' default patterns_dir "../patterns" and a settings path
// "../experiments/id_confusion-detector.toml" resolve as they do for a shipped experiment.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "fuzz_util.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/experiment.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path =
      PATLAB_FUZZ_WORK_DIR "/run/experiment_" + std::to_string(::getpid()) + ".toml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  patlab::fuzz::ExpectInputErrorOnly([&] { (void)patlab::formats::LoadExperimentFile(path); });
  std::remove(path.c_str());
  return 0;
}

// Measured-track CSVs of `patlab analyze` (analysis/analyze.h): the parser, then the whole
// section-II analysis on what parsed (smoothing, gaps, Table I, Wilcoxon pairing, autocorrelation)
// when it is small enough to keep the harness fast.
#include "fuzz_util.h"
#include "patlab/analysis/analyze.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = patlab::fuzz::Text(data, size);
  patlab::fuzz::ExpectInputErrorOnly([&] {
    const std::vector<patlab::analysis::MeasuredTrack> tracks =
        patlab::analysis::ParseTrackCsv(text, "fuzz.csv", patlab::analysis::TrackColumns{});
    size_t samples = 0;
    for (const auto& t : tracks) samples += t.frame.size();
    if (samples > 20000) return;
    (void)patlab::analysis::AnalyzeTracks(tracks, patlab::analysis::AnalyzeOptions{});
  });
  return 0;
}

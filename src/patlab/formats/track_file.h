// Experiment files of the track experiment (format: experiments/table1.toml, documented there).
#pragma once

#include <string>
#include <string_view>

#include "patlab/analysis/track_options.h"

namespace patlab::formats {

// Reads an experiment file and validates it (Check, track_options.h). Problems are InputErrors
// "file:line: message" pointing at the offending key.
analysis::TrackOptions LoadTrackExperiment(const std::string& path);
// The same on TOML text; `source_name` stands for the file in messages.
analysis::TrackOptions ParseTrackExperiment(std::string_view text, const std::string& source_name);

}  // namespace patlab::formats

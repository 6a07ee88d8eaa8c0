// Pieces of the experiment file reader shared by experiment_file.cpp (the known-mode tables and
// LoadExperimentFile) and experiment_file_detect.cpp (the [detect] table). Not part of the public
// API: include experiment_file.h instead.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/io/toml_util.h"
#include "patlab/sim/experiment.h"

namespace patlab::formats::internal {

// Throws the first problem at the line of its key in `r`, the field renamed as `r` describes it
// ("max_iterations" -> "max_iterations in [ml]").
void FailAtFirst(const io::TomlReader& r, const std::vector<OptionsProblem>& problems);

// The value of a number node (integer or float), or nullopt for any other type.
std::optional<double> NumberOf(const toml::node& node);

// The non-empty array at `key` (present): "<key> is empty; expected <expected>" otherwise.
const toml::array& NonEmptyArray(const io::TomlReader& r, std::string_view key,
                                 const std::string& expected);

const toml::table& SubTable(const io::TomlReader& r, std::string_view key);

// A pattern may appear once: its name is the key of its rows in the results.
void CheckNotListed(const std::vector<Pattern>& seen, const std::string& name, const FileLoc& loc);

// Detect mode (experiment_file_detect.cpp): the [detect] table, and `patterns` resolved as
// [[pattern]]s of its detector settings.
void ReadDetectMode(const io::TomlReader& r, const toml::array& patterns,
                    const std::filesystem::path& base, sim::Experiment* e);

}  // namespace patlab::formats::internal

// Reading the small vectors calibration inputs are made of ([x, y] pairs and lists of them) with
// "file:line: what; expected what" messages (docs/architecture.md rule 9).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats::internal {

// Two finite numbers [a, b] as a node, or nullopt for anything else.
std::optional<Vec2> PairOf(const toml::node& node);
// Two finite numbers [a, b]; `expected` names them, e.g. "[x, y] in mm".
Vec2 ReadPair(const io::TomlReader& r, std::string_view key, const std::string& expected);
// A non-empty array of [a, b] pairs.
std::vector<Vec2> ReadPairList(const io::TomlReader& r, std::string_view key,
                               const std::string& expected);
// The array of tables `key` of `root` (empty when absent); anything else is an error.
std::vector<const toml::table*> TableArray(const toml::table& root, std::string_view key,
                                           const std::string& file);

// A path a file names: as given when empty or absolute, else relative to `base_dir` (the file's
// folder), lexically normal.
std::string ResolveBeside(const std::string& base_dir, const std::string& path);

}  // namespace patlab::formats::internal

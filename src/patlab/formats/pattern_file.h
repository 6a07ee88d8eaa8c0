// Pattern files (patterns/*.toml; format documented in patterns/README.md).
#pragma once

#include <string>
#include <string_view>

#include "patlab/core/pattern.h"

namespace patlab::formats {

// Reads and validates a pattern file. Throws InputError naming the file and line of the first
// problem: TOML syntax, unknown keys, wrong types, non-finite numbers, no key or two keys,
// coincident or overlapping patches, orientation pairs out of range or of zero length.
Pattern LoadPatternFile(const std::string& path);
// The same from text; `source_name` stands for the file in messages.
Pattern ParsePattern(std::string_view text, const std::string& source_name);

// Resolves a pattern reference from an experiment or the command line: an existing path, or a
// bare name looked up as <patterns_dir>/<name>.toml.
std::string ResolvePatternPath(const std::string& reference, const std::string& patterns_dir);

}  // namespace patlab::formats

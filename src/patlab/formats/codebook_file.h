// Codebook files (format in patterns/ssl-standard.codebook.toml): the IDs of one pattern as
// colourings of its ID slots, read and checked against the pattern's symmetry.
#pragma once

#include <string>

#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"

namespace patlab::formats {

// Reads a codebook file for `pattern` and checks it against the pattern's symmetry: every
// colouring must be an ID and no two may be the same up to a symmetry rotation. Throws InputError
// "file:line: what is wrong; expected what".
detect::Codebook LoadCodebookFile(const std::string& path, const Pattern& pattern,
                                  const detect::Symmetry& symmetry);
detect::Codebook ParseCodebook(const std::string& text, const std::string& source_name,
                               const Pattern& pattern, const detect::Symmetry& symmetry);

}  // namespace patlab::formats

// The colour vocabulary file (settings/colours.toml; core/colour_names.h says what it is for):
// one [[colour]] table per colour with name, aliases, a typical rgb, hue_deg, saturation,
// lightness and variant_of. The shipped file is built into the library, so every reader resolves
// names without looking for files; another vocabulary is read with LoadColourVocabulary.
#pragma once

#include <string>
#include <string_view>

#include "patlab/core/colour_names.h"
#include "patlab/core/error.h"

namespace patlab::io {

// InputError "file:line: ...; expected ..." for bad syntax, unknown keys, a missing name or rgb,
// values out of range, and a name or alias that two colours share (in any wording).
ColourVocabulary ParseColourVocabulary(std::string_view text, const std::string& name);
ColourVocabulary LoadColourVocabulary(const std::string& path);

// settings/colours.toml as shipped, parsed once.
const ColourVocabulary& DefaultColourVocabulary();

// A name that must be a colour (a detector palette, key and ID colours, a pattern's fixed
// colours, a codebook's colours): its canonical name in DefaultColourVocabulary(), else
// InputError at `loc` (UnknownColourMessage, with a did-you-mean).
std::string CanonicalColour(std::string_view name, const FileLoc& loc);

// A colour class name (thresholds files, CMVision's colors.txt, labels files), which may name a
// class that is no colour ("Ball", "field lines"): the canonical name when it is a colour, the
// name as written when it is no misspelling of one, and InputError at `loc` with a did-you-mean
// when it is one or two edits from a colour ("magneta"; not "a", a mere start of "aqua").
std::string CanonicalClassName(std::string_view name, const FileLoc& loc);

}  // namespace patlab::io

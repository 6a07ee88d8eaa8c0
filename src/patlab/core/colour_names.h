// The colour vocabulary and the one place colour names are resolved. Every reader that names a
// colour (thresholds files and CMVision's colors.txt, labels files, detector settings, pattern
// and scene files) turns what a user wrote into the vocabulary's canonical name here, so that
// names that differ only in wording are one colour: case, spaces, hyphens and underscores do not
// count ("Light Blue", "light_blue", "lightblue" are "light-blue"), and an alias is its colour
// ("magenta" is "pink", "violet" is "purple"). The vocabulary itself is data
// (settings/colours.toml, read by io/colour_vocabulary.h); this header holds no I/O.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace patlab {

struct ColourEntry {
  std::string name;                        // canonical, e.g. "light-blue"
  std::vector<std::string> aliases;        // other wordings, e.g. "sky-blue"
  std::array<uint8_t, 3> rgb = {0, 0, 0};  // a typical sRGB value under field lighting
  double hue_deg = 0.0;                    // HSL hue of the typical value, degrees in [0, 360)
  double saturation = 0.0;                 // HSL saturation, [0, 1]
  double lightness = 0.0;                  // HSL lightness, [0, 1]
  std::string variant_of;                  // "blue" for "light-blue"; empty for a base colour
};

struct ColourVocabulary {
  std::vector<ColourEntry> colours;
  std::string source;  // the file it came from, for messages

  // The entry `name` means in any wording (ColourKey), or null.
  const ColourEntry* Find(std::string_view name) const;
};

// The form names are compared in: ASCII letters lower-cased, spaces, hyphens and underscores
// dropped ("Light Blue" -> "lightblue").
std::string ColourKey(std::string_view name);

// What a name resolves to.
struct ColourResolution {
  bool known = false;  // `name` is a colour of the vocabulary
  std::string name;    // the canonical name when known, else the name as it was written
  // When not known: the canonical names it was probably meant to be (CloseNames on the keys of
  // every name and alias, core/close_names.h), best first; empty when it is close to none.
  std::vector<std::string> close;
  // `close` came from the edit distance (at most 2 edits), not only from `name` being the start
  // of one colour's name ("a" for "aqua"): a misspelling rather than another word.
  bool misspelt = false;
};

ColourResolution ResolveColourName(const ColourVocabulary& vocabulary, std::string_view name);

// The message for a name that did not resolve: "unknown colour 'violett'; expected a colour of
// <source> (did you mean 'purple'?)" or, with nothing close, "...; expected one of <names>".
std::string UnknownColourMessage(const ColourVocabulary& vocabulary,
                                 const ColourResolution& resolution);

}  // namespace patlab

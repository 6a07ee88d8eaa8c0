#include "patlab/io/colour_vocabulary.h"

#include <gtest/gtest.h>

#include "../expect_error.h"

namespace patlab::io {
namespace {

// The names the brief of the vocabulary lists, each with the canonical name it must reach.
TEST(ColourVocabulary, ShippedFileKnowsTheNamesTeamsUse) {
  const ColourVocabulary& v = DefaultColourVocabulary();
  const std::vector<std::pair<std::string, std::string>> expected = {{"orange", "orange"},
                                                                     {"Yellow", "yellow"},
                                                                     {"blue", "blue"},
                                                                     {"Light Blue", "light-blue"},
                                                                     {"dark_blue", "dark-blue"},
                                                                     {"pink", "pink"},
                                                                     {"Magenta", "pink"},
                                                                     {"green", "green"},
                                                                     {"lightgreen", "light-green"},
                                                                     {"Dark Green", "dark-green"},
                                                                     {"cyan", "cyan"},
                                                                     {"purple", "purple"},
                                                                     {"violet", "purple"},
                                                                     {"red", "red"},
                                                                     {"white", "white"},
                                                                     {"black", "black"},
                                                                     {"carpet green", "carpet"},
                                                                     {"lime", "light-green"},
                                                                     {"aqua", "teal"}};
  for (const auto& [wording, canonical] : expected) {
    const ColourEntry* e = v.Find(wording);
    ASSERT_NE(e, nullptr) << wording;
    EXPECT_EQ(e->name, canonical) << wording;
  }
  EXPECT_EQ(v.Find("light-blue")->variant_of, "blue");
  EXPECT_EQ(v.Find("dark-green")->variant_of, "green");
  // Light variants are lighter than their colour, dark ones darker.
  EXPECT_GT(v.Find("light-blue")->lightness, v.Find("blue")->lightness);
  EXPECT_LT(v.Find("dark-blue")->lightness, v.Find("blue")->lightness);
}

TEST(ColourVocabulary, CanonicalColourAndClassName) {
  EXPECT_EQ(CanonicalColour("Sky Blue", FileLoc{"f", 3}), "light-blue");
  EXPECT_INPUT_ERROR(CanonicalColour("pnik", FileLoc{"f", 3}),
                     "f:3: unknown colour 'pnik'; expected a colour of settings/colours.toml (did "
                     "you mean 'pink'?)");
  EXPECT_EQ(CanonicalClassName("Fuchsia", FileLoc{"f", 1}), "pink");
  EXPECT_EQ(CanonicalClassName("Yellow Team", FileLoc{"f", 1}), "Yellow Team");
  EXPECT_INPUT_ERROR(CanonicalClassName("yelow", FileLoc{"f", 2}),
                     "f:2: unknown colour 'yelow'; expected a colour of settings/colours.toml (did "
                     "you mean 'yellow'?)");
}

TEST(ColourVocabulary, TwoColoursSharingAWordingAreRejected) {
  EXPECT_INPUT_ERROR(
      ParseColourVocabulary("[[colour]]\nname = \"pink\"\naliases = [\"magenta\"]\nrgb = [1, 2, "
                            "3]\nhue_deg = 300\nsaturation = 1\nlightness = 0.5\n"
                            "[[colour]]\nname = \"Magenta\"\nrgb = [1, 2, 3]\nhue_deg = 300\n"
                            "saturation = 1\nlightness = 0.5\n",
                            "v.toml"),
      "v.toml:9: 'Magenta' of [[colour]] 2 is already 'pink'; expected every name and alias once "
      "(case, spaces, hyphens and underscores do not count)");
  EXPECT_INPUT_ERROR(ParseColourVocabulary("[[colour]]\nname = \"pink\"\nrgb = [1, 2]\n"
                                           "hue_deg = 300\nsaturation = 1\nlightness = 0.5\n",
                                           "v.toml"),
                     "v.toml:3: rgb in [[colour]] 1 is not [R, G, B]; expected three integers in "
                     "0..255");
}

}  // namespace
}  // namespace patlab::io

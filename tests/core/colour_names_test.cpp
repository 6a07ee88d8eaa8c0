#include "patlab/core/colour_names.h"

#include <gtest/gtest.h>

namespace patlab {
namespace {

// A vocabulary written here, independent of the shipped file.
ColourVocabulary Small() {
  ColourVocabulary v;
  v.source = "small.toml";
  v.colours.push_back({"pink", {"magenta"}, {255, 0, 255}, 300, 1, 0.5, ""});
  v.colours.push_back({"light-blue", {"sky-blue"}, {100, 180, 250}, 208, 0.9, 0.7, "blue"});
  v.colours.push_back({"blue", {}, {0, 0, 255}, 240, 1, 0.5, ""});
  v.colours.push_back({"purple", {"violet"}, {128, 0, 200}, 278, 1, 0.4, ""});
  return v;
}

TEST(ColourNames, KeyIgnoresCaseSpacesHyphensAndUnderscores) {
  EXPECT_EQ(ColourKey("Light Blue"), "lightblue");
  EXPECT_EQ(ColourKey("light_blue"), "lightblue");
  EXPECT_EQ(ColourKey("LIGHT-BLUE"), "lightblue");
  EXPECT_EQ(ColourKey("lightblue"), "lightblue");
  EXPECT_EQ(ColourKey("dark  green"), "darkgreen");
}

TEST(ColourNames, EveryWordingResolvesToTheCanonicalName) {
  const ColourVocabulary v = Small();
  for (const char* wording : {"Light Blue", "light_blue", "lightblue", "light-blue", "LightBlue",
                              "Sky Blue", "sky_blue"}) {
    const ColourResolution r = ResolveColourName(v, wording);
    EXPECT_TRUE(r.known) << wording;
    EXPECT_EQ(r.name, "light-blue") << wording;
  }
  EXPECT_EQ(ResolveColourName(v, "Magenta").name, "pink");
  EXPECT_EQ(ResolveColourName(v, "VIOLET").name, "purple");
  EXPECT_EQ(ResolveColourName(v, "blue").name, "blue");
}

TEST(ColourNames, AMisspeltNameIsCloseToItsColour) {
  const ColourVocabulary v = Small();
  const ColourResolution r = ResolveColourName(v, "Light Bleu");
  EXPECT_FALSE(r.known);
  EXPECT_EQ(r.name, "Light Bleu");
  EXPECT_EQ(r.close, (std::vector<std::string>{"light-blue"}));
  EXPECT_EQ(UnknownColourMessage(v, r),
            "unknown colour 'Light Bleu'; expected a colour of small.toml (did you mean "
            "'light-blue'?)");
  // An alias's misspelling names the canonical colour.
  EXPECT_EQ(ResolveColourName(v, "magneta").close, (std::vector<std::string>{"pink"}));
  EXPECT_TRUE(ResolveColourName(v, "magneta").misspelt);
  // A mere start of one name is suggested but is no misspelling.
  const ColourResolution start = ResolveColourName(v, "vi");
  EXPECT_EQ(start.close, (std::vector<std::string>{"purple"}));
  EXPECT_FALSE(start.misspelt);
}

TEST(ColourNames, AFarNameIsCloseToNothing) {
  const ColourVocabulary v = Small();
  const ColourResolution r = ResolveColourName(v, "Yellow Team");
  EXPECT_FALSE(r.known);
  EXPECT_TRUE(r.close.empty());
  EXPECT_EQ(UnknownColourMessage(v, r),
            "unknown colour 'Yellow Team'; expected a colour of small.toml: 'pink', 'light-blue', "
            "'blue' or 'purple'");
}

}  // namespace
}  // namespace patlab

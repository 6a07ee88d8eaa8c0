#include "patlab/io/colour_vocabulary.h"

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/toml_util.h"

namespace patlab::io {

// The text of settings/colours.toml, generated at configure time (src/patlab/io/CMakeLists.txt).
extern const char* const kShippedColourVocabulary;

namespace {

std::vector<std::string> Aliases(const TomlReader& r) {
  std::vector<std::string> out;
  const toml::node* node = r.table().get("aliases");
  if (node == nullptr) return out;
  const toml::array* array = node->as_array();
  if (array == nullptr)
    r.Fail("aliases",
           r.Describe("aliases") + " is " + TypeName(*node) + "; expected an array of names");
  for (const toml::node& item : *array) {
    const auto* s = item.as_string();
    if (s == nullptr || ColourKey(s->get()).empty()) {
      throw InputError(LocOf(r.file(), item),
                       "aliases holds " + (s == nullptr ? TypeName(item) : "an empty name") +
                           "; expected a colour name");
    }
    out.push_back(s->get());
  }
  return out;
}

std::array<uint8_t, 3> Rgb(const TomlReader& r) {
  const toml::node* node = r.table().get("rgb");
  const toml::array* a = node == nullptr ? nullptr : node->as_array();
  std::array<uint8_t, 3> rgb{};
  bool ok = a != nullptr && a->size() == 3;
  for (size_t k = 0; ok && k < 3; ++k) {
    const auto* v = (*a)[k].as_integer();
    ok = v != nullptr && v->get() >= 0 && v->get() <= 255;
    if (ok) rgb[k] = static_cast<uint8_t>(v->get());
  }
  if (!ok)
    r.Fail("rgb", r.Describe("rgb") + " is not [R, G, B]; expected three integers in 0..255");
  return rgb;
}

double InRange(const TomlReader& r, std::string_view key, double lo, double hi) {
  const double v = r.Number(key);
  if (!(v >= lo && v <= hi)) {
    r.Fail(key, r.Describe(key) + " is " + FormatNumber(v) + "; expected a number in [" +
                    FormatNumber(lo) + ", " + FormatNumber(hi) + "]");
  }
  return v;
}

}  // namespace

ColourVocabulary ParseColourVocabulary(std::string_view text, const std::string& name) {
  const toml::table root = ParseTomlText(text, name);
  const TomlReader top(root, name);
  top.CheckKeys({"colour"});
  const toml::node* node = root.get("colour");
  const toml::array* colours = node == nullptr ? nullptr : node->as_array();
  if (colours == nullptr || colours->empty() || !colours->is_array_of_tables()) {
    throw InputError(
        FileLoc{name, node == nullptr ? 0 : static_cast<int>(node->source().begin.line)},
        "no colours; expected [[colour]] tables");
  }
  ColourVocabulary v;
  v.source = name;
  for (size_t i = 0; i < colours->size(); ++i) {
    const TomlReader r(*colours->get(i)->as_table(), name, "[[colour]] " + std::to_string(i + 1));
    r.CheckKeys({"name", "aliases", "rgb", "hue_deg", "saturation", "lightness", "variant_of"});
    ColourEntry e;
    e.name = r.String("name");
    if (ColourKey(e.name).empty()) r.Fail("name", "empty colour name; expected a name");
    e.aliases = Aliases(r);
    e.rgb = Rgb(r);
    e.hue_deg = InRange(r, "hue_deg", 0.0, 360.0);
    e.saturation = InRange(r, "saturation", 0.0, 1.0);
    e.lightness = InRange(r, "lightness", 0.0, 1.0);
    e.variant_of = r.OptionalString("variant_of").value_or("");
    std::vector<std::string> wordings = e.aliases;
    wordings.insert(wordings.begin(), e.name);
    for (const std::string& w : wordings) {
      if (const ColourEntry* other = v.Find(w)) {
        // Built by appends: GCC 12's -Wrestrict misfires on "literal" + std::string&&.
        std::string message = "'";
        message += EscapeForMessage(w);
        message += "' of [[colour]] ";
        message += std::to_string(i + 1);
        r.Fail("name", message + " is already '" + other->name +
                           "'; expected every name and alias once (case, spaces, hyphens and "
                           "underscores do not count)");
      }
    }
    v.colours.push_back(std::move(e));
  }
  for (const ColourEntry& e : v.colours) {
    if (!e.variant_of.empty() && v.Find(e.variant_of) == nullptr) {
      throw InputError(FileLoc{name, 0}, "colour '" + e.name + "' is a variant of unknown '" +
                                             EscapeForMessage(e.variant_of) +
                                             "'; expected a colour of the file");
    }
  }
  return v;
}

ColourVocabulary LoadColourVocabulary(const std::string& path) {
  return ParseColourVocabulary(ReadTextFile(path, "colour vocabulary"), path);
}

const ColourVocabulary& DefaultColourVocabulary() {
  static const ColourVocabulary vocabulary =
      ParseColourVocabulary(kShippedColourVocabulary, "settings/colours.toml");
  return vocabulary;
}

std::string CanonicalColour(std::string_view name, const FileLoc& loc) {
  const ColourVocabulary& v = DefaultColourVocabulary();
  const ColourResolution r = ResolveColourName(v, name);
  if (!r.known) throw InputError(loc, UnknownColourMessage(v, r));
  return r.name;
}

std::string CanonicalClassName(std::string_view name, const FileLoc& loc) {
  const ColourVocabulary& v = DefaultColourVocabulary();
  const ColourResolution r = ResolveColourName(v, name);
  if (!r.known && r.misspelt) throw InputError(loc, UnknownColourMessage(v, r));
  return r.name;
}

}  // namespace patlab::io

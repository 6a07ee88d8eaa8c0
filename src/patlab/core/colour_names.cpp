#include "patlab/core/colour_names.h"

#include <algorithm>

#include "patlab/core/close_names.h"
#include "patlab/core/error.h"

namespace patlab {

std::string ColourKey(std::string_view name) {
  std::string key;
  for (const char c : name) {
    if (c == ' ' || c == '-' || c == '_' || c == '\t') continue;
    key.push_back(c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
  }
  return key;
}

const ColourEntry* ColourVocabulary::Find(std::string_view name) const {
  const std::string key = ColourKey(name);
  for (const ColourEntry& e : colours) {
    if (ColourKey(e.name) == key) return &e;
    for (const std::string& a : e.aliases) {
      if (ColourKey(a) == key) return &e;
    }
  }
  return nullptr;
}

ColourResolution ResolveColourName(const ColourVocabulary& vocabulary, std::string_view name) {
  ColourResolution r;
  if (const ColourEntry* e = vocabulary.Find(name)) {
    r.known = true;
    r.name = e->name;
    return r;
  }
  r.name = std::string(name);
  // Close names are looked for among the keys, so that "Light Bleu" is close to "light-blue".
  std::vector<std::string> keys;
  std::vector<const ColourEntry*> owners;
  for (const ColourEntry& e : vocabulary.colours) {
    keys.push_back(ColourKey(e.name));
    owners.push_back(&e);
    for (const std::string& a : e.aliases) {
      keys.push_back(ColourKey(a));
      owners.push_back(&e);
    }
  }
  const std::string key = ColourKey(name);
  for (const std::string& k : keys) {
    const int d = EditDistance(key, k);
    if (d <= 2 && d < static_cast<int>(key.size())) r.misspelt = true;
  }
  for (const std::string& close_key : CloseNames(key, keys)) {
    const size_t k =
        static_cast<size_t>(std::find(keys.begin(), keys.end(), close_key) - keys.begin());
    const std::string& canonical = owners[k]->name;
    if (std::find(r.close.begin(), r.close.end(), canonical) == r.close.end()) {
      r.close.push_back(canonical);
    }
  }
  return r;
}

std::string UnknownColourMessage(const ColourVocabulary& vocabulary,
                                 const ColourResolution& resolution) {
  std::string message = "unknown colour '" + EscapeForMessage(resolution.name) +
                        "'; expected a colour of " +
                        (vocabulary.source.empty() ? "the colour vocabulary" : vocabulary.source);
  if (!resolution.close.empty())
    return message + " (did you mean " + QuotedAlternatives(resolution.close) + "?)";
  std::vector<std::string> names;
  for (const ColourEntry& e : vocabulary.colours) names.push_back(e.name);
  return message + ": " + QuotedAlternatives(names);
}

}  // namespace patlab

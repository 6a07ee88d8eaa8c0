#include "patlab/formats/codebook_file.h"

#include <algorithm>

#include "patlab/core/error.h"
#include "patlab/core/options.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

// The "colours" array: distinct colour names, in file order.
std::vector<std::string> ReadColours(const toml::table& root, const io::TomlReader& reader,
                                     const std::string& source_name) {
  const toml::node* colours_node = root.get("colours");
  if (colours_node == nullptr) {
    reader.Fail("colours", "missing colours; expected an array of ID colour names");
  }
  const toml::array* colours = colours_node->as_array();
  if (colours == nullptr || colours->empty()) {
    reader.Fail("colours", "colours is " +
                               (colours == nullptr ? io::TypeName(*colours_node)
                                                   : std::string("an empty array")) +
                               "; expected a non-empty array of ID colour names");
  }
  std::vector<std::string> names;
  for (const toml::node& c : *colours) {
    const auto* s = c.as_string();
    if (s == nullptr) {
      throw InputError(io::LocOf(source_name, c),
                       "colours holds " + io::TypeName(c) + "; expected colour names (strings)");
    }
    const std::string name = io::CanonicalColour(s->get(), io::LocOf(source_name, c));
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      throw InputError(io::LocOf(source_name, c),
                       "colour \"" + s->get() + "\" is listed twice; expected distinct colours");
    }
    names.push_back(name);
  }
  return names;
}

// The [[id]] tables; there must be at least one.
const toml::array& IdTables(const toml::table& root, const std::string& source_name) {
  const toml::node* ids_node = root.get("id");
  const toml::array* ids = ids_node == nullptr ? nullptr : ids_node->as_array();
  if (ids == nullptr || !ids->is_array_of_tables() || ids->empty()) {
    throw InputError(
        ids_node == nullptr ? FileLoc{source_name, 1} : io::LocOf(source_name, *ids_node),
        "no IDs; expected [[id]] tables with id = <integer> and slots = [<colour "
        "per ID slot>]");
  }
  return *ids;
}

// What every [[id]] table is read and checked against.
struct EntryContext {
  const Pattern& pattern;
  const detect::Symmetry& symmetry;
  const std::vector<std::vector<int>>& perms;  // SlotPermutations(pattern, symmetry)
  const detect::Codebook& book;                // colours, num_slots and the entries so far
  const std::string& colour_list;              // book.colours joined by ", " for messages
  const std::vector<int>& lines;               // the line of each entry so far
};

// The id of [[id]] table number e.
int ReadEntryId(const io::TomlReader& er, size_t e) {
  const auto id = er.OptionalInteger("id");
  if (!id) er.Fail("id", "missing id in [[id]] " + std::to_string(e) + "; expected an integer");
  OptionsChecker check;
  check.IntegerInRange("id", *id, 0, 1000000);
  if (!check.problems().empty()) er.Fail("id", check.problems().front().message);
  return static_cast<int>(*id);
}

// The slots array of ID `id`: one colour index per ID slot.
std::vector<int> ReadEntryColours(const io::TomlReader& er, int id, const EntryContext& ctx) {
  const toml::node* slots_node = er.table().get("slots");
  const toml::array* slot_colours = slots_node == nullptr ? nullptr : slots_node->as_array();
  if (slot_colours == nullptr) {
    er.Fail("slots", "ID " + std::to_string(id) +
                         " has no slots array; expected slots = [<colour per ID slot>]");
  }
  const std::vector<std::string>& colours = ctx.book.colours;
  if (static_cast<int>(slot_colours->size()) != ctx.book.num_slots) {
    er.Fail("slots", "ID " + std::to_string(id) + " has " + std::to_string(slot_colours->size()) +
                         " colours; expected " + std::to_string(ctx.book.num_slots) +
                         " (one per ID slot of " + ctx.pattern.name + ")");
  }
  std::vector<int> colour;
  for (const toml::node& c : *slot_colours) {
    const auto* s = c.as_string();
    const std::string name =
        s == nullptr ? std::string() : io::CanonicalColour(s->get(), io::LocOf(er.file(), c));
    const auto it = s == nullptr ? colours.end() : std::find(colours.begin(), colours.end(), name);
    if (it == colours.end()) {
      er.Fail("slots", "ID " + std::to_string(id) + " has colour " +
                           (s == nullptr ? io::TypeName(c) : "\"" + s->get() + "\"") +
                           "; expected one of: " + ctx.colour_list);
    }
    colour.push_back(static_cast<int>(it - colours.begin()));
  }
  return colour;
}

// A colouring that some rotation maps onto itself cannot tell that rotation apart.
void CheckNotAmbiguous(const io::TomlReader& er, const detect::CodebookEntry& entry,
                       const EntryContext& ctx) {
  for (size_t t2 = 1; t2 < ctx.perms.size(); ++t2) {
    if (detect::Stabilises(ctx.perms[t2], entry.colour)) {
      er.Fail("slots", "ID " + std::to_string(entry.id) + " is ambiguous: rotating " +
                           ctx.pattern.name + " by " + detect::DegreesText(ctx.symmetry, t2) +
                           " degrees maps it onto itself; expected colours that fix the "
                           "rotation");
    }
  }
}

// Two entries must differ in id and in colouring up to the pattern's rotations.
void CheckDistinct(const io::TomlReader& er, const detect::CodebookEntry& entry,
                   const EntryContext& ctx) {
  for (size_t other = 0; other < ctx.book.entries.size(); ++other) {
    const detect::CodebookEntry& o = ctx.book.entries[other];
    if (o.id == entry.id) {
      er.Fail("id", "id " + std::to_string(entry.id) + " appears twice (first at line " +
                        std::to_string(ctx.lines[other]) + "); expected distinct IDs");
    }
    for (size_t t2 = 0; t2 < ctx.perms.size(); ++t2) {
      if (detect::Permuted(ctx.perms[t2], o.colour) != entry.colour) continue;
      er.Fail("slots", "ID " + std::to_string(entry.id) +
                           (t2 == 0 ? " has the same colours as ID " + std::to_string(o.id)
                                    : " is ID " + std::to_string(o.id) + " rotated by " +
                                          detect::DegreesText(ctx.symmetry, t2) + " degrees") +
                           "; expected colourings that differ up to the pattern's symmetry");
    }
  }
}

// [[id]] table number e (0-based in messages, as before).
detect::CodebookEntry ReadEntry(const toml::table& t, size_t e, const std::string& source_name,
                                const EntryContext& ctx) {
  const io::TomlReader er(t, source_name, "[[id]] " + std::to_string(e));
  er.CheckKeys({"id", "slots"});
  detect::CodebookEntry entry;
  entry.id = ReadEntryId(er, e);
  entry.colour = ReadEntryColours(er, entry.id, ctx);
  CheckNotAmbiguous(er, entry, ctx);
  CheckDistinct(er, entry, ctx);
  return entry;
}

}  // namespace

detect::Codebook ParseCodebook(const std::string& text, const std::string& source_name,
                               const Pattern& pattern, const detect::Symmetry& symmetry) {
  const toml::table root = io::ParseTomlText(text, source_name);
  io::TomlReader reader(root, source_name);
  reader.CheckKeys({"pattern", "colours", "id"});
  detect::Codebook book;
  book.pattern = reader.String("pattern");
  if (book.pattern != pattern.name) {
    reader.Fail("pattern", "pattern is \"" + book.pattern + "\"; expected \"" + pattern.name +
                               "\" (the pattern this codebook is loaded for)");
  }
  book.colours = ReadColours(root, reader, source_name);
  std::string colour_list;
  for (const std::string& c : book.colours) colour_list += (colour_list.empty() ? "" : ", ") + c;

  book.num_slots = static_cast<int>(detect::IdSlots(pattern).size());
  const toml::array& ids = IdTables(root, source_name);
  const std::vector<std::vector<int>> perms = detect::SlotPermutations(pattern, symmetry);
  std::vector<int> lines;
  const EntryContext ctx{pattern, symmetry, perms, book, colour_list, lines};
  for (size_t e = 0; e < ids.size(); ++e) {
    const toml::table& t = *ids.get(e)->as_table();
    detect::CodebookEntry entry = ReadEntry(t, e, source_name, ctx);
    lines.push_back(io::LocOf(source_name, t).line);
    book.entries.push_back(std::move(entry));
  }
  std::sort(
      book.entries.begin(), book.entries.end(),
      [](const detect::CodebookEntry& a, const detect::CodebookEntry& b) { return a.id < b.id; });
  return book;
}

detect::Codebook LoadCodebookFile(const std::string& path, const Pattern& pattern,
                                  const detect::Symmetry& symmetry) {
  return ParseCodebook(io::ReadTextFile(path, "TOML file"), path, pattern, symmetry);
}

}  // namespace patlab::formats

#include "patlab/detect/codebook.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/options.h"
#include "patlab/io/toml_util.h"

namespace patlab::detect {

namespace {

// For each effective shift, the permutation of ID slots it induces: slot k moves to slot perm[k].
std::vector<std::vector<int>> SlotPermutations(const Pattern& pattern, const Symmetry& symmetry) {
  const int m = static_cast<int>(symmetry.circular_order.size());
  std::vector<int> circular_position(pattern.size(), -1);
  for (int j = 0; j < m; ++j) circular_position[symmetry.circular_order[j]] = j;
  const std::vector<int> slots = IdSlots(pattern);
  std::vector<int> slot_of_patch(pattern.size(), -1);
  for (int k = 0; k < static_cast<int>(slots.size()); ++k) slot_of_patch[slots[k]] = k;
  std::vector<std::vector<int>> perms;
  for (int shift : symmetry.effective_shifts) {
    std::vector<int> perm(slots.size());
    for (int k = 0; k < static_cast<int>(slots.size()); ++k) {
      const int to = symmetry.circular_order[(circular_position[slots[k]] + shift) % m];
      perm[k] = slot_of_patch[to];
      PATLAB_CHECK(perm[k] >= 0);  // effective shifts map ID slots to ID slots
    }
    perms.push_back(std::move(perm));
  }
  return perms;
}

bool Stabilises(const std::vector<int>& perm, const std::vector<int>& colour) {
  for (size_t k = 0; k < perm.size(); ++k) {
    if (colour[perm[k]] != colour[k]) return false;
  }
  return true;
}

// The colouring moved by `perm`: the colour of slot k goes to slot perm[k].
std::vector<int> Permuted(const std::vector<int>& perm, const std::vector<int>& colour) {
  std::vector<int> out(colour.size());
  for (size_t k = 0; k < perm.size(); ++k) out[perm[k]] = colour[k];
  return out;
}

int CountCycles(const std::vector<int>& perm) {
  std::vector<bool> seen(perm.size(), false);
  int cycles = 0;
  for (size_t k = 0; k < perm.size(); ++k) {
    if (seen[k]) continue;
    ++cycles;
    for (size_t j = k; !seen[j]; j = perm[j]) seen[j] = true;
  }
  return cycles;
}

int Moebius(int d) {
  int result = 1;
  for (int p = 2; p * p <= d; ++p) {
    if (d % p != 0) continue;
    d /= p;
    if (d % p == 0) return 0;
    result = -result;
  }
  if (d > 1) result = -result;
  return result;
}

int64_t CheckedPower(int64_t base, int exponent) {
  int64_t result = 1;
  for (int i = 0; i < exponent; ++i) {
    if (result > (int64_t{1} << 62) / base) {
      throw InputError(std::to_string(base) + "^" + std::to_string(exponent) +
                       " colourings are too many to count; expected fewer colours or ID slots");
    }
    result *= base;
  }
  return result;
}

// The rotation angle of effective shift number t, in degrees in [0, 360), for messages.
std::string DegreesText(const Symmetry& symmetry, size_t t) {
  double deg = symmetry.fits[symmetry.effective_shifts[t]].angle_rad * 180.0 / std::numbers::pi;
  if (deg < 0.0) deg += 360.0;
  return FormatNumber(std::round(deg * 10.0) / 10.0);
}

}  // namespace

std::vector<int> IdSlots(const Pattern& pattern) {
  std::vector<int> slots;
  for (int i = 0; i < pattern.size(); ++i) {
    if (pattern.patches[i].role == PatchRole::kId) slots.push_back(i);
  }
  return slots;
}

namespace {

// The least-squares rotation about the key that maps circular position j onto j + shift (2-D
// Procrustes about a fixed centre, Umeyama 1991), and the worst patch distance under it.
ShiftFit FitShift(const std::vector<Vec2>& q, int shift) {
  const int m = static_cast<int>(q.size());
  ShiftFit fit;
  fit.shift = shift;
  double dot = 0.0, cross = 0.0;
  for (int j = 0; j < m; ++j) {
    const Vec2& a = q[j];
    const Vec2& b = q[(j + shift) % m];
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  fit.angle_rad = shift == 0 ? 0.0 : std::atan2(cross, dot);
  const double c = std::cos(fit.angle_rad), s = std::sin(fit.angle_rad);
  for (int j = 0; j < m; ++j) {
    const Vec2& a = q[j];
    const Vec2 rotated(c * a.x() - s * a.y(), s * a.x() + c * a.y());
    fit.residual_mm = std::max(fit.residual_mm, (rotated - q[(j + shift) % m]).norm());
  }
  return fit;
}

bool PreservesRoles(const Pattern& pattern, const std::vector<int>& circular_order, int shift) {
  const int m = static_cast<int>(circular_order.size());
  for (int j = 0; j < m; ++j) {
    const Patch& from = pattern.patches[circular_order[j]];
    const Patch& to = pattern.patches[circular_order[(j + shift) % m]];
    if (from.role != to.role || (from.role == PatchRole::kFixed && from.colour != to.colour)) {
      return false;
    }
  }
  return true;
}

}  // namespace

Symmetry FindSymmetry(const Pattern& pattern, double tolerance_mm) {
  PATLAB_CHECK(tolerance_mm >= 0.0);
  Symmetry symmetry;
  symmetry.tolerance_mm = tolerance_mm;
  const Vec2 key = pattern.patches[pattern.key_index].position_mm;
  std::vector<std::pair<double, int>> by_angle;
  for (int i = 0; i < pattern.size(); ++i) {
    if (i == pattern.key_index) continue;
    const Vec2 q = pattern.patches[i].position_mm - key;
    by_angle.push_back({std::atan2(q.y(), q.x()), i});
  }
  std::sort(by_angle.begin(), by_angle.end());
  std::vector<Vec2> q;
  for (const auto& [angle, index] : by_angle) {
    symmetry.circular_order.push_back(index);
    q.push_back(pattern.patches[index].position_mm - key);
  }

  const int m = static_cast<int>(q.size());
  int generator = m;  // gcd of m and the accepted shifts: the group is its multiples
  for (int shift = 0; shift < m; ++shift) {
    ShiftFit fit = FitShift(q, shift);
    fit.accepted = fit.residual_mm <= tolerance_mm || shift == 0;
    fit.preserves_roles = PreservesRoles(pattern, symmetry.circular_order, shift);
    if (fit.accepted) {
      symmetry.shifts.push_back(shift);
      symmetry.angles_rad.push_back(fit.angle_rad);
      generator = std::gcd(generator, shift);
    }
    symmetry.fits.push_back(fit);
  }
  for (ShiftFit& fit : symmetry.fits) {
    fit.in_group = fit.shift % generator == 0;
    if (!fit.in_group) continue;
    symmetry.group_shifts.push_back(fit.shift);
    if (fit.preserves_roles) symmetry.effective_shifts.push_back(fit.shift);
  }
  return symmetry;
}

std::string SymmetrySummary(const Symmetry& symmetry) {
  auto list = [](const std::vector<int>& shifts) {
    std::string text;
    for (int s : shifts) text += (text.empty() ? "{" : ", ") + std::to_string(s);
    return text + "}";
  };
  const int k = symmetry.effective_order();
  const std::string head = "accepted shifts " + list(symmetry.shifts) + ", group generated " +
                           list(symmetry.group_shifts);
  if (k == 1) return head + ": geometry and fixed colours fix the rotation";
  return head + ", ID colours decide among " + list(symmetry.effective_shifts) + ": " +
         std::to_string(k) + " rotations";
}

std::string SymmetryTable(const Symmetry& symmetry, const std::string& indent) {
  std::string out = indent + "shift  angle deg  residual mm  geometry (tolerance " +
                    FormatNumber(symmetry.tolerance_mm) +
                    " mm)                      rotation decided by\n";
  for (const ShiftFit& fit : symmetry.fits) {
    double deg = fit.angle_rad * 180.0 / std::numbers::pi;
    if (deg < 0.0) deg += 360.0;
    const char* geometry = fit.shift == 0 ? "identity"
                           : fit.accepted ? "accepted: residual <= tolerance"
                           : fit.in_group ? "rejected, but composed of accepted shifts"
                                          : "rejected: residual > tolerance";
    const char* decided = fit.shift == 0         ? "-"
                          : !fit.in_group        ? "geometry"
                          : !fit.preserves_roles ? "fixed colours"
                                                 : "ID colours";
    out += indent + StringPrintf("%-5d  %-9s  %-11s  %-46s %s\n", fit.shift,
                                 FormatFixed(deg, 1).c_str(),
                                 FormatFixed(fit.residual_mm, 2).c_str(), geometry, decided);
  }
  return out;
}

uint64_t CountIds(const Pattern& pattern, const Symmetry& symmetry, int num_colours) {
  PATLAB_CHECK(num_colours >= 1);
  const std::vector<std::vector<int>> perms = SlotPermutations(pattern, symmetry);
  const int k = symmetry.effective_order();
  // The effective shifts form a subgroup of Z_m, generated by its smallest positive element;
  // its subgroup of order d is generated by element k / d.
  for (int t = 0; t < k; ++t) {
    PATLAB_CHECK(symmetry.effective_shifts[t] == t * (k > 1 ? symmetry.effective_shifts[1] : 0));
  }
  int64_t free_colourings = 0;
  for (int d = 1; d <= k; ++d) {
    if (k % d != 0) continue;
    const int mu = Moebius(d);
    if (mu == 0) continue;
    const int cycles = CountCycles(perms[(k / d) % k]);
    free_colourings += mu * CheckedPower(num_colours, cycles);
  }
  PATLAB_CHECK(free_colourings % k == 0);
  return static_cast<uint64_t>(free_colourings / k);
}

bool Confusable(const Pattern& pattern, const Symmetry& symmetry, const std::vector<int>& a,
                const std::vector<int>& b) {
  for (const std::vector<int>& perm : SlotPermutations(pattern, symmetry)) {
    if (Permuted(perm, a) == b) return true;
  }
  return false;
}

int StabilisingShift(const Pattern& pattern, const Symmetry& symmetry,
                     const std::vector<int>& colour) {
  const std::vector<std::vector<int>> perms = SlotPermutations(pattern, symmetry);
  for (size_t t = 1; t < perms.size(); ++t) {
    if (Stabilises(perms[t], colour)) return symmetry.effective_shifts[t];
  }
  return 0;
}

Codebook GenerateCodebook(const Pattern& pattern, const Symmetry& symmetry,
                          const std::vector<std::string>& colours) {
  PATLAB_CHECK(!colours.empty());
  Codebook book;
  book.pattern = pattern.name;
  book.colours = colours;
  book.num_slots = static_cast<int>(IdSlots(pattern).size());
  const int n = static_cast<int>(colours.size());
  const int64_t total = CheckedPower(n, book.num_slots);
  if (total > (int64_t{1} << 24)) {
    throw InputError(std::to_string(n) + "^" + std::to_string(book.num_slots) +
                     " colourings are too many to list; expected at most 2^24");
  }
  const std::vector<std::vector<int>> perms = SlotPermutations(pattern, symmetry);
  std::vector<int> colour(book.num_slots);
  for (int64_t code = 0; code < total; ++code) {
    int64_t rest = code;
    for (int k = book.num_slots - 1; k >= 0; --k) {
      colour[k] = static_cast<int>(rest % n);
      rest /= n;
    }
    bool keep = true;
    for (size_t t = 1; t < perms.size() && keep; ++t) {
      // An ID needs a trivial stabiliser, and each rotation class is listed once: by its
      // lexicographically smallest member (std::vector compares lexicographically).
      keep = !Stabilises(perms[t], colour) && !(Permuted(perms[t], colour) < colour);
    }
    if (keep) book.entries.push_back({static_cast<int>(book.entries.size()), colour});
  }
  return book;
}

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
    if (std::find(names.begin(), names.end(), s->get()) != names.end()) {
      throw InputError(io::LocOf(source_name, c),
                       "colour \"" + s->get() + "\" is listed twice; expected distinct colours");
    }
    names.push_back(s->get());
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
  const Symmetry& symmetry;
  const std::vector<std::vector<int>>& perms;  // SlotPermutations(pattern, symmetry)
  const Codebook& book;                        // colours, num_slots and the entries so far
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
    const auto it =
        s == nullptr ? colours.end() : std::find(colours.begin(), colours.end(), s->get());
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
void CheckNotAmbiguous(const io::TomlReader& er, const CodebookEntry& entry,
                       const EntryContext& ctx) {
  for (size_t t2 = 1; t2 < ctx.perms.size(); ++t2) {
    if (Stabilises(ctx.perms[t2], entry.colour)) {
      er.Fail("slots", "ID " + std::to_string(entry.id) + " is ambiguous: rotating " +
                           ctx.pattern.name + " by " + DegreesText(ctx.symmetry, t2) +
                           " degrees maps it onto itself; expected colours that fix the "
                           "rotation");
    }
  }
}

// Two entries must differ in id and in colouring up to the pattern's rotations.
void CheckDistinct(const io::TomlReader& er, const CodebookEntry& entry, const EntryContext& ctx) {
  for (size_t other = 0; other < ctx.book.entries.size(); ++other) {
    const CodebookEntry& o = ctx.book.entries[other];
    if (o.id == entry.id) {
      er.Fail("id", "id " + std::to_string(entry.id) + " appears twice (first at line " +
                        std::to_string(ctx.lines[other]) + "); expected distinct IDs");
    }
    for (size_t t2 = 0; t2 < ctx.perms.size(); ++t2) {
      if (Permuted(ctx.perms[t2], o.colour) != entry.colour) continue;
      er.Fail("slots", "ID " + std::to_string(entry.id) +
                           (t2 == 0 ? " has the same colours as ID " + std::to_string(o.id)
                                    : " is ID " + std::to_string(o.id) + " rotated by " +
                                          DegreesText(ctx.symmetry, t2) + " degrees") +
                           "; expected colourings that differ up to the pattern's symmetry");
    }
  }
}

// [[id]] table number e (0-based in messages, as before).
CodebookEntry ReadEntry(const toml::table& t, size_t e, const std::string& source_name,
                        const EntryContext& ctx) {
  const io::TomlReader er(t, source_name, "[[id]] " + std::to_string(e));
  er.CheckKeys({"id", "slots"});
  CodebookEntry entry;
  entry.id = ReadEntryId(er, e);
  entry.colour = ReadEntryColours(er, entry.id, ctx);
  CheckNotAmbiguous(er, entry, ctx);
  CheckDistinct(er, entry, ctx);
  return entry;
}

}  // namespace

Codebook ParseCodebook(const std::string& text, const std::string& source_name,
                       const Pattern& pattern, const Symmetry& symmetry) {
  const toml::table root = io::ParseTomlText(text, source_name);
  io::TomlReader reader(root, source_name);
  reader.CheckKeys({"pattern", "colours", "id"});
  Codebook book;
  book.pattern = reader.String("pattern");
  if (book.pattern != pattern.name) {
    reader.Fail("pattern", "pattern is \"" + book.pattern + "\"; expected \"" + pattern.name +
                               "\" (the pattern this codebook is loaded for)");
  }
  book.colours = ReadColours(root, reader, source_name);
  std::string colour_list;
  for (const std::string& c : book.colours) colour_list += (colour_list.empty() ? "" : ", ") + c;

  book.num_slots = static_cast<int>(IdSlots(pattern).size());
  const toml::array& ids = IdTables(root, source_name);
  const std::vector<std::vector<int>> perms = SlotPermutations(pattern, symmetry);
  std::vector<int> lines;
  const EntryContext ctx{pattern, symmetry, perms, book, colour_list, lines};
  for (size_t e = 0; e < ids.size(); ++e) {
    const toml::table& t = *ids.get(e)->as_table();
    CodebookEntry entry = ReadEntry(t, e, source_name, ctx);
    lines.push_back(io::LocOf(source_name, t).line);
    book.entries.push_back(std::move(entry));
  }
  std::sort(book.entries.begin(), book.entries.end(),
            [](const CodebookEntry& a, const CodebookEntry& b) { return a.id < b.id; });
  return book;
}

Codebook LoadCodebookFile(const std::string& path, const Pattern& pattern,
                          const Symmetry& symmetry) {
  return ParseCodebook(io::ReadTextFile(path, "TOML file"), path, pattern, symmetry);
}

}  // namespace patlab::detect

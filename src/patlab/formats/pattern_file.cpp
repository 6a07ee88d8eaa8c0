#include "patlab/formats/pattern_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>

#include "patlab/core/format.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/name.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

using patlab::FormatNumber;

constexpr double kMaxPatternExtentMm = 1e4;

std::string PointText(const Vec2& p) {
  return "(" + FormatNumber(p.x()) + ", " + FormatNumber(p.y()) + ")";
}

// A length (mm) in (0, kMaxPatternExtentMm]: `value` read from `key`, named `what` in messages.
void CheckLength(const io::TomlReader& pr, std::string_view key, const std::string& what,
                 double value) {
  if (!(value > 0.0)) {
    pr.Fail(key, what + " is " + FormatNumber(value) + "; expected a positive number (mm)");
  }
  if (!(value <= kMaxPatternExtentMm)) {
    pr.Fail(key, what + " is " + FormatNumber(value) + "; expected at most " +
                     FormatNumber(kMaxPatternExtentMm) + " (mm)");
  }
}

// The patch's outline: shape = "disc" (default) with radius, or "rectangle" with size = [sx, sy]
// and an optional angle_deg.
void ParseShape(const io::TomlReader& pr, size_t i, Patch* patch) {
  const std::string shape = pr.OptionalString("shape").value_or("disc");
  const std::optional<PatchShape> parsed = FindName(shape, kPatchShapeNames);
  if (!parsed) {
    pr.Fail("shape",
            pr.Describe("shape") + " is \"" + shape + "\"; expected " + NameList(kPatchShapeNames));
  }
  const std::string which = "[[patch]] " + std::to_string(i);
  if (*parsed == PatchShape::kDisc) {
    for (std::string_view key : {"size", "angle_deg"}) {
      if (pr.Has(key)) {
        pr.Fail(key, which + " is a disc with " + std::string(key) +
                         "; expected radius only, or shape = \"rectangle\"");
      }
    }
    patch->radius_mm = pr.Number("radius");
    CheckLength(pr, "radius", pr.Describe("radius"), patch->radius_mm);
    return;
  }
  if (pr.Has("radius")) {
    pr.Fail("radius", which +
                          " is a rectangle with a radius; expected size = [sx, sy] (mm) and "
                          "no radius");
  }
  const toml::node* size_node = pr.table().get("size");
  const toml::array* size = size_node ? size_node->as_array() : nullptr;
  if (size == nullptr || size->size() != 2 || !size->get(0)->is_number() ||
      !size->get(1)->is_number()) {
    pr.Fail("size", which + " is a rectangle " +
                        (size_node ? "whose size is not two numbers" : "without size") +
                        "; expected size = [sx, sy] (mm, the sides along the rectangle's x and y)");
  }
  const Vec2 sides(size->get(0)->value<double>().value(), size->get(1)->value<double>().value());
  CheckLength(pr, "size", "size[0] in " + which, sides.x());
  CheckLength(pr, "size", "size[1] in " + which, sides.y());
  const double angle_deg = pr.OptionalNumber("angle_deg").value_or(0.0);
  if (!(std::abs(angle_deg) <= 360.0)) {
    pr.Fail("angle_deg", pr.Describe("angle_deg") + " is " + FormatNumber(angle_deg) +
                             "; expected an angle in [-360, 360] (degrees)");
  }
  const Patch r =
      RectanglePatch(patch->position_mm, sides, angle_deg * std::numbers::pi / 180.0, patch->role);
  patch->shape = r.shape;
  patch->size_mm = r.size_mm;
  patch->angle_rad = r.angle_rad;
  patch->radius_mm = r.radius_mm;
}

// One [[patch]] table, number i. `key_index` is the first key patch seen so far (-1: none).
Patch ParsePatch(const toml::table& t, const std::string& file, size_t i, int key_index) {
  io::TomlReader pr(t, file, "[[patch]] " + std::to_string(i));
  pr.CheckKeys({"x", "y", "radius", "role", "colour", "shape", "size", "angle_deg"});
  Patch patch;
  // A pattern sits on a robot: coordinates beyond 10 m are a typo, and 1e300 would overflow the
  // squared distances of every estimator and bound.
  const auto coordinate = [&pr](std::string_view key) {
    const double v = pr.Number(key);
    if (!(std::abs(v) <= kMaxPatternExtentMm)) {
      pr.Fail(key, pr.Describe(key) + " is " + FormatNumber(v) + "; expected a coordinate in [" +
                       FormatNumber(-kMaxPatternExtentMm) + ", " +
                       FormatNumber(kMaxPatternExtentMm) + "] (mm)");
    }
    return v;
  };
  patch.position_mm = Vec2(coordinate("x"), coordinate("y"));
  ParseShape(pr, i, &patch);
  const std::string role = pr.String("role");
  const std::optional<PatchRole> parsed = FindName(role, kPatchRoleNames);
  if (!parsed) {
    pr.Fail("role",
            pr.Describe("role") + " is \"" + role + "\"; expected " + NameList(kPatchRoleNames));
  }
  patch.role = *parsed;
  if (patch.role == PatchRole::kKey && key_index >= 0) {
    pr.Fail("role", "second key patch ([[patch]] " + std::to_string(i) +
                        "; the first is [[patch]] " + std::to_string(key_index) +
                        "); expected exactly one patch with role = \"key\"");
  }
  patch.colour = pr.OptionalString("colour").value_or("");
  if (!patch.colour.empty()) patch.colour = io::CanonicalColour(patch.colour, pr.Loc("colour"));
  if (patch.role == PatchRole::kFixed && patch.colour.empty()) {
    pr.Fail("role", "[[patch]] " + std::to_string(i) +
                        " has role \"fixed\" but no colour; expected colour = \"<name>\"");
  }
  if (patch.role == PatchRole::kId && !patch.colour.empty()) {
    pr.Fail("colour", "[[patch]] " + std::to_string(i) +
                          " is an ID slot with a colour; expected no colour (the codebook "
                          "assigns it) or role = \"fixed\"");
  }
  return patch;
}

// Every [[patch]] table into pattern->patches and key_index; their locations into *locs.
void ParsePatches(const toml::table& root, const std::string& file, Pattern* pattern,
                  std::vector<FileLoc>* locs) {
  const toml::node* patches_node = root.get("patch");
  if (patches_node == nullptr) {
    throw InputError(FileLoc{file, 1},
                     "no patches; expected at least 2 [[patch]] tables (orientation needs two "
                     "distinct patch positions)");
  }
  const toml::array* patches = patches_node->as_array();
  if (patches == nullptr || !patches->is_array_of_tables()) {
    throw InputError(io::LocOf(file, *patches_node),
                     "patch is " + io::TypeName(*patches_node) + "; expected [[patch]] tables");
  }
  int key_index = -1;
  for (size_t i = 0; i < patches->size(); ++i) {
    const toml::table& t = *patches->get(i)->as_table();
    pattern->patches.push_back(ParsePatch(t, file, i, key_index));
    if (pattern->patches.back().role == PatchRole::kKey) key_index = static_cast<int>(i);
    locs->push_back(io::LocOf(file, t));
  }
  pattern->key_index = std::max(key_index, 0);
  const int n = pattern->size();
  if (n < 2) {
    throw InputError(locs->empty() ? FileLoc{file, 1} : locs->back(),
                     "pattern has " + std::to_string(n) +
                         " patch; expected at least 2 (orientation needs two distinct patch "
                         "positions)");
  }
  if (n > kMaxPatches) {
    throw InputError((*locs)[kMaxPatches], "pattern has " + std::to_string(n) +
                                               " patches; expected at most " +
                                               std::to_string(kMaxPatches));
  }
  if (key_index < 0) {
    throw InputError(locs->front(), "no key patch; expected exactly one patch with role = \"key\"");
  }
}

// Patches must not coincide or overlap.
void CheckPatchLayout(const Pattern& pattern, const std::vector<FileLoc>& locs) {
  for (int i = 0; i < pattern.size(); ++i) {
    for (int j = 0; j < i; ++j) {
      const Patch& a = pattern.patches[j];
      const Patch& b = pattern.patches[i];
      const double distance = (a.position_mm - b.position_mm).norm();
      if (distance < 1e-6) {
        throw InputError(locs[i], "[[patch]] " + std::to_string(i) + " coincides with [[patch]] " +
                                      std::to_string(j) + " at " + PointText(b.position_mm) +
                                      "; expected distinct patch positions");
      }
      if (a.shape != PatchShape::kDisc || b.shape != PatchShape::kDisc) {
        const double gap = PatchGap(a, b);
        if (gap < -1e-9) {
          throw InputError(locs[i], "[[patch]] " + std::to_string(i) + " (" +
                                        std::string(NameOf(b.shape, kPatchShapeNames)) +
                                        ") overlaps [[patch]] " + std::to_string(j) + " (" +
                                        std::string(NameOf(a.shape, kPatchShapeNames)) + ") by " +
                                        FormatNumber(-gap) +
                                        " mm; expected patches that do not overlap");
        }
        continue;
      }
      if (distance < a.radius_mm + b.radius_mm - 1e-9) {
        throw InputError(locs[i], "[[patch]] " + std::to_string(i) + " overlaps [[patch]] " +
                                      std::to_string(j) + ": centres " + FormatNumber(distance) +
                                      " mm apart, radii " + FormatNumber(b.radius_mm) + " + " +
                                      FormatNumber(a.radius_mm) +
                                      " mm; expected centre distance >= sum of radii");
      }
    }
  }
}

// Orientation pair k, [from, to], checked against n patches and the pairs before it.
OrientationPair ParseOrientationPair(const toml::node& item, const FileLoc& loc, size_t k, int n,
                                     const std::vector<OrientationPair>& seen,
                                     const std::string& expected) {
  const toml::array* pair = item.as_array();
  if (pair == nullptr || pair->size() != 2 || !pair->get(0)->is_integer() ||
      !pair->get(1)->is_integer()) {
    throw InputError(loc,
                     "orientation pair " + std::to_string(k) + " is not two integers; " + expected);
  }
  const int64_t from = pair->get(0)->as_integer()->get();
  const int64_t to = pair->get(1)->as_integer()->get();
  const std::string name = "orientation pair " + std::to_string(k) + " [" + std::to_string(from) +
                           ", " + std::to_string(to) + "]";
  for (int64_t index : {from, to}) {
    if (index < 0 || index >= n) {
      throw InputError(loc, name + ": patch index " + std::to_string(index) +
                                " out of range; expected 0.." + std::to_string(n - 1));
    }
  }
  if (from == to) {
    throw InputError(loc, name + " has zero length; expected two different patches");
  }
  const OrientationPair op{static_cast<int>(from), static_cast<int>(to)};
  for (const OrientationPair& s : seen) {
    if (s == op || (s.from == op.to && s.to == op.from)) {
      throw InputError(loc, name + " is listed twice; expected each pair once");
    }
  }
  return op;
}

std::vector<OrientationPair> ParseOrientationPairs(const toml::node& pairs_node,
                                                   const std::string& file, int n) {
  const toml::array* pairs = pairs_node.as_array();
  const std::string expected =
      "expected an array of [from, to] patch index pairs, e.g. [[1, 2], [3, 4]]";
  if (pairs == nullptr || pairs->empty()) {
    throw InputError(io::LocOf(file, pairs_node),
                     "orientation_pairs is " +
                         (pairs == nullptr ? io::TypeName(pairs_node) : std::string("empty")) +
                         "; " + expected);
  }
  std::vector<OrientationPair> result;
  for (size_t k = 0; k < pairs->size(); ++k) {
    const toml::node& item = *pairs->get(k);
    result.push_back(ParseOrientationPair(item, io::LocOf(file, item), k, n, result, expected));
  }
  return result;
}

Pattern ParseTable(const toml::table& root, const std::string& file) {
  io::TomlReader reader(root, file);
  reader.CheckKeys({"name", "description", "orientation_pairs", "patch"});
  Pattern pattern;
  pattern.name = reader.String("name");
  if (pattern.name.empty()) reader.Fail("name", "name is empty; expected a non-empty string");
  if (const std::string problem = io::NameProblem(pattern.name); !problem.empty()) {
    reader.Fail("name", "name '" + EscapeForMessage(pattern.name) + "' " + problem + "; expected " +
                            io::kNameExpected);
  }
  pattern.description = reader.OptionalString("description").value_or("");
  std::vector<FileLoc> patch_locs;
  ParsePatches(root, file, &pattern, &patch_locs);
  CheckPatchLayout(pattern, patch_locs);
  if (const toml::node* pairs_node = root.get("orientation_pairs")) {
    pattern.orientation_pairs = ParseOrientationPairs(*pairs_node, file, pattern.size());
  } else {
    pattern.orientation_pairs = DefaultOrientationPairs(pattern.patches, pattern.key_index);
  }
  return pattern;
}

}  // namespace

Pattern LoadPatternFile(const std::string& path) {
  return ParseTable(io::ParseTomlFile(path), path);
}

Pattern ParsePattern(std::string_view text, const std::string& source_name) {
  return ParseTable(io::ParseTomlText(text, source_name), source_name);
}

std::string ResolvePatternPath(const std::string& reference, const std::string& patterns_dir) {
  namespace fs = std::filesystem;
  // The error_code overloads: a name the file system refuses (too long, a symlink loop) is an
  // InputError saying so, never an exception of another type (found by fuzzing).
  std::error_code ec;
  if (fs::exists(reference, ec)) return reference;
  ThrowIfPathUnusable(reference, ec);
  const fs::path candidate = fs::path(patterns_dir) / (reference + ".toml");
  if (fs::exists(candidate, ec)) return candidate.string();
  throw InputError("pattern '" + reference +
                   "' not found; expected a pattern file path or a name in " + patterns_dir + "/");
}

}  // namespace patlab::formats

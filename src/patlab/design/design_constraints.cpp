// The constraints file of `patlab design --constraints FILE` (design/design.h,
// docs/file-formats.md).
#include <climits>
#include <cmath>
#include <string>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/design.h"
#include "patlab/io/toml_util.h"

namespace patlab::design {

namespace {

using io::TomlReader;

// An integer key into an int field; values beyond int name the key at its line.
void ReadInt(const TomlReader& r, std::string_view key, int* field) {
  const auto v = r.OptionalInteger(key);
  if (!v) return;
  if (*v < INT_MIN || *v > INT_MAX) {
    r.Fail(key, r.Describe(key) + " is " + std::to_string(*v) +
                    "; expected an integer of at most " + std::to_string(INT_MAX) + " in size");
  }
  *field = static_cast<int>(*v);
}

void ReadNumber(const TomlReader& r, std::string_view key, double* field) {
  if (const auto v = r.OptionalNumber(key)) *field = *v;
}

// id_radii_mm: one number, or an array of numbers (one per ID patch).
void ReadRadii(const TomlReader& r, DesignOptions* o) {
  const toml::node* node = r.table().get("id_radii_mm");
  if (node == nullptr) return;
  if (const auto* a = node->as_array()) {
    o->id_radii_mm.clear();
    for (const toml::node& item : *a) {
      const auto v = item.value<double>();
      if (!item.is_number() || !v || !std::isfinite(*v)) {
        throw InputError(io::LocOf(r.file(), item),
                         "id_radii_mm holds " + io::TypeName(item) +
                             "; expected an array of numbers (mm), one per ID patch");
      }
      o->id_radii_mm.push_back(*v);
    }
    if (o->id_radii_mm.empty()) {
      r.Fail("id_radii_mm", "id_radii_mm is empty; expected a number or one per ID patch (mm)");
    }
    return;
  }
  o->id_radii_mm = {r.Number("id_radii_mm")};
}

template <typename E, size_t N>
void ReadName(const TomlReader& r, std::string_view key, const EnumNames<E, N>& names, E* field) {
  const auto v = r.OptionalString(key);
  if (!v) return;
  const auto value = FindName(*v, names);
  if (!value) {
    r.Fail(key, std::string(key) + " is \"" + *v + "\"; expected " + NameList(names));
  }
  *field = *value;
}

}  // namespace

DesignOptions ParseDesignConstraints(std::string_view text, const std::string& file,
                                     DesignOptions o) {
  const toml::table root = io::ParseTomlText(text, file);
  const TomlReader r(root, file);
  r.CheckKeys({"name", "outer_diameter_mm", "rim_gap_mm", "key_radius_mm", "id_patches",
               "id_radii_mm", "min_gap_mm", "palette", "tolerance_mm", "objective", "symmetry",
               "min_ids", "min_rotation_onset_mm", "max_angle_crlb_mrad_per_mm",
               "max_position_crlb_per_mm", "starts", "max_evaluations", "seed"});
  if (const auto name = r.OptionalString("name")) o.name = *name;
  ReadNumber(r, "outer_diameter_mm", &o.outer_diameter_mm);
  ReadNumber(r, "rim_gap_mm", &o.rim_gap_mm);
  ReadNumber(r, "key_radius_mm", &o.key_radius_mm);
  ReadInt(r, "id_patches", &o.id_patches);
  ReadRadii(r, &o);
  ReadNumber(r, "min_gap_mm", &o.min_gap_mm);
  ReadInt(r, "palette", &o.palette);
  ReadNumber(r, "tolerance_mm", &o.tolerance_mm);
  ReadName(r, "objective", kDesignObjectiveNames, &o.objective);
  ReadName(r, "symmetry", kDesignSymmetryNames, &o.symmetry);
  if (const auto v = r.OptionalInteger("min_ids")) o.min_ids = *v;
  ReadNumber(r, "min_rotation_onset_mm", &o.min_rotation_onset_mm);
  ReadNumber(r, "max_angle_crlb_mrad_per_mm", &o.max_angle_crlb_mrad_per_mm);
  ReadNumber(r, "max_position_crlb_per_mm", &o.max_position_crlb_per_mm);
  ReadInt(r, "starts", &o.starts);
  ReadInt(r, "max_evaluations", &o.max_evaluations);
  if (const auto seed = r.OptionalInteger("seed")) {
    if (*seed < 0)
      r.Fail("seed", "seed is " + std::to_string(*seed) + "; expected an integer >= 0");
    o.seed = static_cast<uint64_t>(*seed);
  }
  // Every other limit (ranges, dots that cannot fit) at the line of the key it names.
  io::ThrowFirstProblemAt(root, file, Check(o));
  return o;
}

DesignOptions LoadDesignConstraints(const std::string& path, DesignOptions defaults) {
  io::CheckInputFile(path, "design constraints TOML file", io::kMaxTextFileBytes);
  return ParseDesignConstraints(io::ReadTextFile(path, "design constraints TOML file"), path,
                                std::move(defaults));
}

}  // namespace patlab::design

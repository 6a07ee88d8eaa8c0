// The checks of DesignOptions (design.h): every field's range, then the geometric impossibilities
// that no search can fix.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/design.h"
#include "patlab/design/design_internal.h"
#include "patlab/detect/codebook.h"

namespace patlab::design {

using internal::IdRadius;
using internal::InnerRadius;
using internal::MaxIds;
using internal::RequiredIds;

namespace {

// The geometric impossibilities that no search can fix (checked once every field is in range).
void CheckFits(const DesignOptions& o, OptionsChecker* check) {
  const double inner = InnerRadius(o);
  if (o.key_radius_mm > inner) {
    check->Require("key_radius_mm", o.key_radius_mm, false,
                   "at most outer_diameter_mm / 2 - rim_gap_mm = " + FormatNumber(inner) +
                       " (the key patch must fit in the robot top)");
    return;
  }
  const double ring = 0.5 * (inner - o.key_radius_mm - o.min_gap_mm);
  for (int i = 0; i < static_cast<int>(o.id_radii_mm.size()); ++i) {
    check->Require("id_radii_mm", o.id_radii_mm[i], o.id_radii_mm[i] <= ring,
                   "at most (outer_diameter_mm / 2 - rim_gap_mm - key_radius_mm - min_gap_mm) / 2"
                   " = " +
                       FormatNumber(ring) +
                       " (an ID patch must fit between the key patch and the rim)");
  }
  if (!check->problems().empty()) return;
  // Necessary for any layout: the discs of radius r_i + gap/2 are disjoint, lie inside the disc
  // of radius inner + gap/2 and outside the key's disc of radius r_key + gap/2.
  const double half_gap = 0.5 * o.min_gap_mm;
  const double room = std::pow(inner + half_gap, 2) - std::pow(o.key_radius_mm + half_gap, 2);
  double need = 0.0;
  for (int i = 0; i < o.id_patches; ++i) need += std::pow(IdRadius(o, i) + half_gap, 2);
  if (need > room) {
    check->Require("id_patches", o.id_patches, false,
                   "fewer ID patches of these radii: with half of min_gap_mm around each they "
                   "cover " +
                       FormatFixed(std::numbers::pi * need, 0) + " mm^2, more than the " +
                       FormatFixed(std::numbers::pi * room, 0) +
                       " mm^2 between the key patch and the rim");
  }
}

// A cyclic family accepts every rotation by 360/id_patches: its ID capacity is that of the regular
// layout (the same for every member), counted once before the search.
void CheckCyclic(const DesignOptions& o, OptionsChecker* check) {
  const double rho = 0.5 * (o.key_radius_mm + o.min_gap_mm + InnerRadius(o));
  const double x[2] = {rho, 0.0};
  const Pattern regular = DesignPattern(o, ExpandSymmetry(o, x));
  const uint64_t ids =
      detect::CountIds(regular, detect::FindSymmetry(regular, o.tolerance_mm), o.palette);
  if (RequiredIds(o) > ids) {
    check->Fail("min_ids", "symmetry cyclic leaves " + std::to_string(ids) + " IDs with " +
                               std::to_string(o.palette) +
                               " colours; expected min_ids <= " + std::to_string(ids) +
                               " (0 asks for all " + std::to_string(MaxIds(o)) + ")");
  }
}

}  // namespace

std::vector<OptionsProblem> Check(const DesignOptions& o) {
  OptionsChecker check;
  const bool name_ok =
      !o.name.empty() && o.name.size() <= 100 &&
      std::all_of(o.name.begin(), o.name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
      });
  if (!name_ok) {
    check.Fail("name",
               "name is \"" + o.name + "\"; expected 1 to 100 letters, digits, '-', '_' or '.'");
  }
  check.Positive("outer_diameter_mm", o.outer_diameter_mm, "mm")
      .NonNegative("rim_gap_mm", o.rim_gap_mm, "mm")
      .Positive("key_radius_mm", o.key_radius_mm, "mm")
      .IntegerInRange("id_patches", o.id_patches, 1, kMaxPatches - 1)
      .NonNegative("min_gap_mm", o.min_gap_mm, "mm")
      .IntegerInRange("palette", o.palette, 2, 8)
      .NonNegative("tolerance_mm", o.tolerance_mm, "mm")
      .NonNegative("min_rotation_onset_mm", o.min_rotation_onset_mm, "mm")
      .Require("max_angle_crlb_mrad_per_mm", o.max_angle_crlb_mrad_per_mm,
               o.max_angle_crlb_mrad_per_mm > 0, "a number > 0 or inf (mrad/mm)")
      .Require("max_position_crlb_per_mm", o.max_position_crlb_per_mm,
               o.max_position_crlb_per_mm > 0, "a number > 0 or inf (mm/mm)")
      .IntegerInRange("starts", o.starts, 1, 100000)
      .IntegerInRange("max_evaluations", o.max_evaluations, 10, 10000000)
      .Positive("xtol_mm", o.xtol_mm, "mm");
  const bool count_ok = o.id_patches >= 1 && o.id_patches < kMaxPatches;
  if (count_ok && o.palette >= 2 && o.palette <= 8) {
    check.IntegerInRange("min_ids", o.min_ids, 0, static_cast<int64_t>(MaxIds(o)));
  }
  if (o.id_radii_mm.size() != 1 && (!count_ok || o.id_radii_mm.size() != size_t(o.id_patches))) {
    check.Fail("id_radii_mm", "id_radii_mm has " + std::to_string(o.id_radii_mm.size()) +
                                  " values; expected 1 or id_patches (" +
                                  std::to_string(o.id_patches) + ")");
  }
  for (double r : o.id_radii_mm) check.Positive("id_radii_mm", r, "mm");
  if (!o.start_mm.empty() && o.start_mm.size() != size_t(o.id_patches)) {
    check.Fail("start_mm", "start_mm has " + std::to_string(o.start_mm.size()) +
                               " positions; expected none or id_patches (" +
                               std::to_string(o.id_patches) + ")");
  }
  if (check.problems().empty()) CheckFits(o, &check);
  if (check.problems().empty() && o.symmetry == DesignSymmetry::kCyclic) CheckCyclic(o, &check);
  return check.Take();
}

void Validate(const DesignOptions& options) { ThrowFirstProblem(Check(options)); }

}  // namespace patlab::design

// Identification capacity of a pattern (paper section III, Table II): which colourings of its ID
// slots can be told apart once the detector has found the pattern.
//
// The detector sorts the non-key patches by angle around the key and must find the rotational
// correspondence of that circular order with the model's. A rotation about the key that maps the
// pattern's patches onto themselves within a distance tolerance (the paper's rule of thumb:
// distances that differ by more than 10 mm are told apart) cannot be decided by geometry; only
// colours can decide it. Hence:
//  - the symmetry group G of a pattern is the set of such rotations (a cyclic group, found from
//    the geometry), restricted to those that map ID slots to ID slots and every fixed-colour patch
//    to a patch of the same fixed colour (others are always told apart by the fixed colours);
//  - a colouring of the ID slots is an ID only if no rotation in G other than the identity maps
//    it onto itself (otherwise the rotation stays ambiguous), and the colourings that G maps onto
//    each other are one ID (counted once per rotation class).
// Where G is trivial (the Butterfly / SSL standard pattern) every colouring is an ID.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "patlab/core/pattern.h"

namespace patlab::detect {

// The rotational symmetry of a pattern about its key patch.
struct Symmetry {
  double tolerance_mm = 0.0;
  // The non-key patch indices sorted by angle about the key patch (atan2 in (-pi, pi],
  // ascending): the circular order in which the detector sees them.
  std::vector<int> circular_order;
  // Every rotation about the key that maps the non-key patches onto themselves within
  // tolerance_mm, as a circular shift s: circular position j goes to (j + s) mod m. shifts[0] is
  // the identity (0); ascending.
  std::vector<int> shifts;
  std::vector<double> angles_rad;  // the least-squares rotation angle of each shift
  // The subset of `shifts` that also preserves patch roles and fixed colours (see above): the
  // group that decides identification. Ascending, starts with 0.
  std::vector<int> effective_shifts;

  int order() const { return static_cast<int>(shifts.size()); }
  int effective_order() const { return static_cast<int>(effective_shifts.size()); }
};

// Finds the rotations about the key patch that map every non-key patch to within tolerance_mm of
// a non-key patch (tolerance_mm >= 0).
Symmetry FindSymmetry(const Pattern& pattern, double tolerance_mm);

// The patch indices of the ID slots (role kId) in patch order: the slot order of codebooks.
std::vector<int> IdSlots(const Pattern& pattern);

// The number of IDs with `num_colours` ID colours (>= 1), by Burnside / Moebius inversion over
// the cyclic group: #colourings with trivial stabiliser = sum over d | k of mu(d) n^c(d), where
// c(d) is the number of ID-slot cycles of the rotation generating the order-d subgroup; each ID
// is a rotation class of k of them. Exact for any pattern size (no enumeration).
uint64_t CountIds(const Pattern& pattern, const Symmetry& symmetry, int num_colours);

struct CodebookEntry {
  int id = 0;               // the ID reported for this colouring (>= 0)
  std::vector<int> colour;  // per ID slot (IdSlots order): index into Codebook::colours
};

// The IDs of one pattern: colourings of its ID slots, in IdSlots order.
struct Codebook {
  std::string pattern;               // the pattern's name
  std::vector<std::string> colours;  // ID colour names (without the key / team colours)
  int num_slots = 0;
  std::vector<CodebookEntry> entries;  // sorted by id; ids distinct
};

// Every ID of `pattern` for the ID colours `colours` (names, distinct, >= 1): the colourings with
// a trivial stabiliser in symmetry.effective_shifts, one per rotation class (the lexicographically
// smallest, slot 0 most significant), numbered 0, 1, ... in that lexicographic order. Throws
// InputError when there are more than 2^24 colourings to enumerate.
Codebook GenerateCodebook(const Pattern& pattern, const Symmetry& symmetry,
                          const std::vector<std::string>& colours);

// Reads a codebook file (format in patterns/ssl-standard.codebook.toml) for `pattern` and checks
// it against the pattern's symmetry: every colouring must be an ID and no two may be the same up
// to a symmetry rotation. Throws InputError "file:line: what is wrong; expected what".
Codebook LoadCodebookFile(const std::string& path, const Pattern& pattern,
                          const Symmetry& symmetry);
Codebook ParseCodebook(const std::string& text, const std::string& source_name,
                       const Pattern& pattern, const Symmetry& symmetry);

// The rotation shift in symmetry.effective_shifts, other than 0, that maps `colour` (one entry
// per ID slot) onto itself, or 0 when the colouring is an ID.
int StabilisingShift(const Pattern& pattern, const Symmetry& symmetry,
                     const std::vector<int>& colour);

}  // namespace patlab::detect

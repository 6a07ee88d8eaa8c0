#include "patlab/detect/codebook.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/options.h"

namespace patlab::detect {

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

namespace {

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

}  // namespace

// The rotation angle of effective shift number t, in degrees in [0, 360), for messages.
std::string DegreesText(const Symmetry& symmetry, size_t t) {
  double deg = symmetry.fits[symmetry.effective_shifts[t]].angle_rad * 180.0 / std::numbers::pi;
  if (deg < 0.0) deg += 360.0;
  return FormatNumber(std::round(deg * 10.0) / 10.0);
}

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

// Size classes of the patches: radii sorted, a new class wherever two neighbours' diameters
// differ by more than tolerance_mm (single linkage, so that "of the same size" is an equivalence
// and the shifts that keep it form a group). The key is classed with the others; no shift moves it.
std::vector<int> SizeClasses(const Pattern& pattern, double tolerance_mm) {
  std::vector<std::pair<double, int>> by_radius;
  for (int i = 0; i < pattern.size(); ++i) by_radius.emplace_back(pattern.patches[i].radius_mm, i);
  std::sort(by_radius.begin(), by_radius.end());
  std::vector<int> size_class(pattern.size(), 0);
  int current = 0;
  for (size_t k = 1; k < by_radius.size(); ++k) {
    if (2.0 * (by_radius[k].first - by_radius[k - 1].first) > tolerance_mm) ++current;
    size_class[by_radius[k].second] = current;
  }
  return size_class;
}

bool PreservesRoles(const Pattern& pattern, const std::vector<int>& size_class,
                    const std::vector<int>& circular_order, int shift) {
  const int m = static_cast<int>(circular_order.size());
  for (int j = 0; j < m; ++j) {
    const int a = circular_order[j], b = circular_order[(j + shift) % m];
    const Patch& from = pattern.patches[a];
    const Patch& to = pattern.patches[b];
    if (from.role != to.role || (from.role == PatchRole::kFixed && from.colour != to.colour) ||
        size_class[a] != size_class[b]) {
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
  const std::vector<int> size_class = SizeClasses(pattern, tolerance_mm);
  int generator = m;  // gcd of m and the accepted shifts: the group is its multiples
  for (int shift = 0; shift < m; ++shift) {
    ShiftFit fit = FitShift(q, shift);
    fit.accepted = fit.residual_mm <= tolerance_mm || shift == 0;
    fit.preserves_roles = PreservesRoles(pattern, size_class, symmetry.circular_order, shift);
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
                          : !fit.preserves_roles ? "fixed colours or sizes"
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

}  // namespace patlab::detect

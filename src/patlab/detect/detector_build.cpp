// Detector construction: the configuration checked, and each pattern precomputed into the
// PatternRuntime the stages read (circular order, code table, centred models, tolerances, reach).
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/detect/detector_internal.h"

namespace patlab::detect {

using internal::kFixedAny;
using internal::kMaxLabels;

namespace {

double ChiSquaredQuantile(int dof, double p) {
  return boost::math::quantile(boost::math::chi_squared(dof), p);
}

Pattern WithoutPatch(const Pattern& pattern, int missing) {
  Pattern reduced;
  reduced.name = pattern.name;
  std::vector<int> new_index(pattern.size(), -1);
  for (int i = 0; i < pattern.size(); ++i) {
    if (i == missing) continue;
    new_index[i] = reduced.size();
    reduced.patches.push_back(pattern.patches[i]);
  }
  reduced.key_index = new_index[pattern.key_index];
  for (const OrientationPair& pair : pattern.orientation_pairs) {
    if (pair.from == missing || pair.to == missing) continue;
    reduced.orientation_pairs.push_back({new_index[pair.from], new_index[pair.to]});
  }
  if (reduced.orientation_pairs.empty()) {
    reduced.orientation_pairs = DefaultOrientationPairs(reduced.patches, reduced.key_index);
  }
  return reduced;
}

}  // namespace

// Model positions centred on the centroid of the patches fitted: variant 0 is the full fit,
// variant 1 + k the fit without circular position k.
void internal::BuildCentredModels(const Pattern& pattern, PatternRuntime* rt) {
  const Vec2 key = pattern.patches[rt->key_index].position_mm;
  for (int variant = 0; variant <= rt->mk; ++variant) {
    const int skip = variant - 1;  // circular position left out, or -1
    Vec2 centroid = key;
    int count = 1;
    for (int j = 0; j < rt->mk; ++j) {
      if (j == skip) continue;
      centroid += pattern.patches[rt->circ_patch[j]].position_mm;
      ++count;
    }
    centroid /= count;
    rt->key_centred[variant] = key - centroid;
    rt->sq[variant] = rt->key_centred[variant].squaredNorm();
    for (int j = 0; j < rt->mk; ++j) {
      rt->circ_centred[variant][j] = pattern.patches[rt->circ_patch[j]].position_mm - centroid;
      if (j != skip) rt->sq[variant] += rt->circ_centred[variant][j].squaredNorm();
    }
    const int r = skip < 0 ? rt->mk : rt->mk - 1;
    for (int k = 0; k < 2 * r; ++k) {
      const int c = skip < 0 ? k % rt->mk : (skip + 1 + k % r) % rt->mk;
      rt->ring[variant][k] = c;
      rt->ring_centred[variant][k] = rt->circ_centred[variant][c];
    }
  }
}

int Detector::Impl::LabelOf(const std::string& name) const {
  const auto& palette = config.palette;
  const auto it = std::find(palette.begin(), palette.end(), name);
  return it == palette.end() ? -1 : static_cast<int>(it - palette.begin());
}

void Detector::Impl::CheckPalette() const {
  const std::vector<std::string>& palette = config.palette;
  if (palette.empty() || static_cast<int>(palette.size()) > kMaxLabels) {
    throw InputError("palette has " + std::to_string(palette.size()) +
                     " colours; expected 1 to 64 colour names");
  }
  for (size_t i = 0; i < palette.size(); ++i) {
    if (palette[i].empty()) {
      throw InputError("palette colour " + std::to_string(i) + " is empty; expected a colour name");
    }
    if (std::find(palette.begin(), palette.begin() + static_cast<long>(i), palette[i]) !=
        palette.begin() + static_cast<long>(i)) {
      throw InputError("palette colour \"" + palette[i] +
                       "\" is listed twice; expected distinct colour names");
    }
  }
}

void Detector::Impl::Build() {
  CheckPalette();
  Validate(config.options);
  if (config.patterns.empty()) throw InputError("no patterns; expected at least one pattern");
  for (int p = 0; p < static_cast<int>(config.patterns.size()); ++p) {
    runtimes.push_back(BuildRuntime(p));
  }
  // Stage 2's lists: one per distinct (neighbour colours, neighbour area range).
  for (int p = 0; p < static_cast<int>(runtimes.size()); ++p) {
    const PatternRuntime& rt = runtimes[p];
    int list = static_cast<int>(neighbour_lists.size());
    for (int q = 0; q < p; ++q) {
      const PatternRuntime& earlier = runtimes[q];
      if (earlier.neighbour_mask == rt.neighbour_mask && earlier.nb_area_min == rt.nb_area_min &&
          earlier.nb_area_max == rt.nb_area_max) {
        list = neighbour_list_of[q];
        break;
      }
    }
    if (list == static_cast<int>(neighbour_lists.size())) neighbour_lists.emplace_back();
    neighbour_list_of.push_back(list);
  }
}

Detector::Impl::PatternRuntime Detector::Impl::BuildRuntime(int p) {
  const DetectorOptions& o = config.options;
  const DetectorPattern& dp = config.patterns[p];
  const Pattern& pattern = dp.pattern;
  const std::string where = "pattern " + pattern.name + ": ";
  PatternRuntime rt;
  rt.m = pattern.size();
  rt.mk = rt.m - 1;
  rt.key_index = pattern.key_index;
  if (o.max_neighbours < rt.mk) {
    throw InputError(where + "max_neighbours is " + std::to_string(o.max_neighbours) +
                     "; expected at least " + std::to_string(rt.mk) + " (its non-key patches)");
  }
  if (dp.key_colours.empty()) {
    throw InputError(where + "no key colours; expected at least one team colour");
  }
  for (const std::string& name : dp.key_colours) {
    const int label = LabelOf(name);
    if (label < 0) throw InputError(where + "key colour \"" + name + "\" is not in the palette");
    patterns_by_key_label[label].push_back(p);
    key_label_mask |= uint64_t{1} << label;
  }
  const Symmetry symmetry = FindSymmetry(pattern, dp.symmetry_tolerance_mm);
  for (int j = 0; j < rt.mk; ++j) rt.circ_patch[j] = symmetry.circular_order[j];
  BuildCodebook(dp, where, &rt);
  BuildCircularColours(pattern, where, &rt);
  internal::BuildCentredModels(pattern, &rt);
  BuildTolerancesAndReach(pattern, &rt);
  rt.model = estimate::Model::FromPattern(pattern);
  if (rt.can_fit_missing) {
    for (int i = 0; i < rt.m; ++i) {
      if (i != rt.key_index) {
        rt.missing_model[i] = estimate::Model::FromPattern(WithoutPatch(pattern, i));
      }
    }
  }
  return rt;
}

// The codebook's colours in the palette, and a dense table from the base-n code of the slot
// colours to the ID.
void Detector::Impl::BuildCodebook(const DetectorPattern& dp, const std::string& where,
                                   PatternRuntime* rt) const {
  const Codebook& book = dp.codebook;
  const size_t num_slots = IdSlots(dp.pattern).size();
  if (book.num_slots != static_cast<int>(num_slots)) {
    throw InputError(where + "codebook has " + std::to_string(book.num_slots) +
                     " slots; expected " + std::to_string(num_slots) + " (its ID slots)");
  }
  rt->codebook_colour.fill(-1);
  rt->num_codebook_colours = static_cast<int>(book.colours.size());
  for (int c = 0; c < rt->num_codebook_colours; ++c) {
    const int label = LabelOf(book.colours[c]);
    if (label < 0) {
      throw InputError(where + "codebook colour \"" + book.colours[c] + "\" is not in the palette");
    }
    rt->codebook_colour[label] = static_cast<int8_t>(c);
    rt->neighbour_mask |= uint64_t{1} << label;
  }
  int64_t table_size = 1;
  for (size_t s = 0; s < num_slots; ++s) {
    table_size *= std::max(1, rt->num_codebook_colours);
    if (table_size > (int64_t{1} << 22)) {
      throw InputError(where +
                       "codebook has too many colourings for the lookup table; "
                       "expected colours^slots <= 2^22");
    }
  }
  rt->code_to_id.assign(table_size, -1);
  for (const CodebookEntry& e : book.entries) {
    int64_t code = 0;
    for (int c : e.colour) code = code * rt->num_codebook_colours + c;
    rt->code_to_id[code] = e.id;
  }
}

// Per circular position: the fixed colour's label, or kFixedAny and the code weight of its ID
// slot (slot s of S weighs colours^(S - 1 - s), as the code table is laid out).
void Detector::Impl::BuildCircularColours(const Pattern& pattern, const std::string& where,
                                          PatternRuntime* rt) const {
  const std::vector<int> slots = IdSlots(pattern);
  for (int j = 0; j < rt->mk; ++j) {
    const Patch& patch = pattern.patches[rt->circ_patch[j]];
    if (patch.role == PatchRole::kFixed) {
      rt->fixed_label[j] = LabelOf(patch.colour);
      if (rt->fixed_label[j] < 0) {
        throw InputError(where + "fixed patch colour \"" + patch.colour +
                         "\" is not in the palette");
      }
      rt->neighbour_mask |= uint64_t{1} << rt->fixed_label[j];
      rt->slot_weight[j] = 0;
      continue;
    }
    rt->fixed_label[j] = kFixedAny;
    const int slot =
        static_cast<int>(std::find(slots.begin(), slots.end(), rt->circ_patch[j]) - slots.begin());
    int weight = 1;
    for (int s = slot + 1; s < static_cast<int>(slots.size()); ++s) {
      weight *= rt->num_codebook_colours;
    }
    rt->slot_weight[j] = weight;
  }
}

// The geometric tolerances (stage 4), and the areas and ring distances of stages 1-2.
void Detector::Impl::BuildTolerancesAndReach(const Pattern& pattern, PatternRuntime* rt) {
  const DetectorOptions& o = config.options;
  // Paper section III: an n-patch rigid fit leaves 2n - 3 degrees of freedom of residual. The
  // calibration's residual adds to each blob's noise (EffectiveSigma2Mm2).
  const double sigma2 = EffectiveSigma2Mm2(o);
  rt->dof_full = 2 * rt->m - 3;
  rt->e_max_full = sigma2 * ChiSquaredQuantile(rt->dof_full, o.geometry_confidence);
  rt->dof_missing = 2 * (rt->m - 1) - 3;
  rt->can_fit_missing = o.missing_patch == MissingPatchPolicy::kFit && rt->dof_missing >= 1;
  if (rt->can_fit_missing) {
    rt->e_max_missing = sigma2 * ChiSquaredQuantile(rt->dof_missing, o.geometry_confidence);
  }

  const Vec2 key = pattern.patches[rt->key_index].position_mm;
  // Areas of the patch outlines (disc or rectangle); a patch's position is its centroid.
  const double key_area = pattern.patches[rt->key_index].Area();
  rt->key_area_min = o.area_ratio_min * key_area;
  rt->key_area_max = o.area_ratio_max * key_area;
  rt->nb_area_min = 1e300;
  rt->nb_area_max = 0.0;
  rt->ring_min_mm = 1e300;
  rt->ring_max_mm = 0.0;
  for (int j = 0; j < rt->mk; ++j) {
    const Patch& patch = pattern.patches[rt->circ_patch[j]];
    const double area = patch.Area();
    rt->nb_area_min = std::min(rt->nb_area_min, o.area_ratio_min * area);
    rt->nb_area_max = std::max(rt->nb_area_max, o.area_ratio_max * area);
    const double r = (patch.position_mm - key).norm();
    rt->ring_min_mm = std::min(rt->ring_min_mm, r);
    rt->ring_max_mm = std::max(rt->ring_max_mm, r);
  }
  const double inner = std::max(0.0, rt->ring_min_mm - o.reach_margin_mm);
  rt->reach_min2 = inner * inner;
  rt->reach_max_mm = rt->ring_max_mm + o.reach_margin_mm;
  rt->reach_max2 = rt->reach_max_mm * rt->reach_max_mm;
  max_reach_mm = std::max(max_reach_mm, rt->reach_max_mm);
}

}  // namespace patlab::detect

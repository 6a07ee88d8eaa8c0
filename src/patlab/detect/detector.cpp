#include "patlab/detect/detector.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "patlab/core/error.h"
#include "patlab/io/toml_util.h"

namespace patlab::detect {

std::string_view MissingPatchPolicyName(MissingPatchPolicy policy) {
  switch (policy) {
    case MissingPatchPolicy::kReject:
      return "reject";
    case MissingPatchPolicy::kFit:
      return "fit";
  }
  return "?";
}

std::string_view DetectionStatusName(DetectionStatus status) {
  switch (status) {
    case DetectionStatus::kOk:
      return "ok";
    case DetectionStatus::kMissingPatch:
      return "missing_patch";
    case DetectionStatus::kAmbiguous:
      return "ambiguous";
  }
  return "?";
}

long DetectStageTimes::StagesSum() const {
  return key_candidates_ns + neighbours_ns + radial_sort_ns + correspondences_ns + colours_ns +
         conflicts_ns + pose_ns;
}

DetectStageTimes& DetectStageTimes::operator+=(const DetectStageTimes& o) {
  key_candidates_ns += o.key_candidates_ns;
  neighbours_ns += o.neighbours_ns;
  radial_sort_ns += o.radial_sort_ns;
  correspondences_ns += o.correspondences_ns;
  colours_ns += o.colours_ns;
  conflicts_ns += o.conflicts_ns;
  pose_ns += o.pose_ns;
  total_ns += o.total_ns;
  return *this;
}

DetectStats& DetectStats::operator+=(const DetectStats& o) {
  time += o.time;
  key_candidates += o.key_candidates;
  neighbours += o.neighbours;
  neighbours_cut += o.neighbours_cut;
  correspondences += o.correspondences;
  geometry_passed += o.geometry_passed;
  colour_rejected += o.colour_rejected;
  ambiguous += o.ambiguous;
  missing_fits += o.missing_fits;
  conflicts += o.conflicts;
  detections += o.detections;
  return *this;
}

std::optional<OptionsProblem> ValidateDetectorOptions(const DetectorOptions& o) {
  auto problem = [](std::string field, double value, std::string expected) {
    return OptionsProblem{
        field, field + " is " + io::FormatNumber(value) + "; expected " + std::move(expected)};
  };
  if (!(o.patch_sigma_mm > 0.0) || !std::isfinite(o.patch_sigma_mm)) {
    return problem("patch_sigma_mm", o.patch_sigma_mm, "a finite number > 0 (mm)");
  }
  if (!(o.geometry_confidence > 0.0 && o.geometry_confidence < 1.0)) {
    return problem("geometry_confidence", o.geometry_confidence, "a probability in (0, 1)");
  }
  if (!(o.reach_margin_mm >= 0.0) || !std::isfinite(o.reach_margin_mm)) {
    return problem("reach_margin_mm", o.reach_margin_mm, "a finite number >= 0 (mm)");
  }
  if (!(o.area_ratio_min >= 0.0) || !std::isfinite(o.area_ratio_min)) {
    return problem("area_ratio_min", o.area_ratio_min, "a finite number >= 0");
  }
  if (!(o.area_ratio_max > o.area_ratio_min) || !std::isfinite(o.area_ratio_max)) {
    return problem("area_ratio_max", o.area_ratio_max,
                   "a finite number > area_ratio_min (" + io::FormatNumber(o.area_ratio_min) + ")");
  }
  if (o.max_neighbours < 1 || o.max_neighbours > 16) {
    return problem("max_neighbours", o.max_neighbours, "an integer in [1, 16]");
  }
  if (o.ml.max_iterations < 1) {
    return problem("ml_max_iterations", o.ml.max_iterations, "an integer >= 1");
  }
  return std::nullopt;
}

// Upper regularised incomplete gamma Q(dof / 2, e / 2): the probability that a chi-square variable
// with integer `dof` exceeds e, in closed form (Abramowitz & Stegun 26.4.4-26.4.5): cheaper than
// the general algorithm by two orders of magnitude.
double ChiSquaredSurvival(int dof, double e) {
  PATLAB_CHECK(dof >= 1);
  const double y = 0.5 * e;
  const double decay = std::exp(-y);
  if (dof % 2 == 0) {
    double term = 1.0, sum = 1.0;  // sum_{i < dof/2} y^i / i!
    for (int i = 1; i < dof / 2; ++i) {
      term *= y / i;
      sum += term;
    }
    return std::min(1.0, decay * sum);
  }
  double q = std::erfc(std::sqrt(y));                   // Q(1/2, y)
  double term = 2.0 * std::sqrt(y / std::numbers::pi);  // y^(1/2) / Gamma(3/2)
  for (int i = 0; i < dof / 2; ++i) {
    q += decay * term;  // Q(a + 1, y) = Q(a, y) + y^a e^-y / Gamma(a + 1), a = i + 1/2
    term *= y / (i + 1.5);
  }
  return std::min(1.0, q);
}

namespace {

constexpr int kMaxLabels = 64;
constexpr int kMaxGathered = 64;  // neighbours collected before the max_neighbours cut
constexpr int kFixedAny = -2;     // circular position holds an ID slot, not a fixed colour

struct PatternRuntime {
  int m = 0;   // patches
  int mk = 0;  // non-key patches, in circular order
  int key_index = 0;
  std::array<int, kMaxPatches> circ_patch{};  // patch index at circular position j
  // Model positions centred on the centroid of the patches fitted. Index [0] of the arrays is
  // the full fit; [1 + k] the fit without circular position k.
  std::array<Vec2, kMaxPatches + 1> key_centred{};
  std::array<std::array<Vec2, kMaxPatches>, kMaxPatches + 1> circ_centred{};
  std::array<double, kMaxPatches + 1> sq{};
  double e_max_full = 0.0, e_max_missing = 0.0;
  int dof_full = 0, dof_missing = 0;
  bool can_fit_missing = false;
  std::array<int, kMaxPatches> fixed_label{};  // per circular position; kFixedAny: ID slot
  std::array<int, kMaxPatches> slot_weight{};  // per circular position: code weight of its slot
  std::array<int8_t, kMaxLabels> codebook_colour{};  // palette label -> codebook colour, or -1
  int num_codebook_colours = 0;
  std::vector<int> code_to_id;  // dense: base-n code of the slot colours -> ID or -1
  uint64_t neighbour_mask = 0;
  double key_area_min = 0.0, key_area_max = 0.0;
  double nb_area_min = 0.0, nb_area_max = 0.0;
  double ring_min_mm = 0.0, ring_max_mm = 0.0;  // model distances of non-key patches from key
  double reach_min2 = 0.0, reach_max2 = 0.0, reach_max_mm = 0.0;
  estimate::Model model;
  std::array<estimate::Model, kMaxPatches> missing_model{};  // by missing patch index
};

struct Candidate {
  double score = 0.0;  // E / tolerance; lower is better
  double e = 0.0;
  int pattern = 0;
  int key_blob = 0;
  int id = -1;
  DetectionStatus status = DetectionStatus::kOk;
  int missing_patch = -1;
  int num_blobs = 0;  // blobs explained (patches found)
  std::array<int, kMaxPatches> blob{};
};

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

// Stage timing (DetectStats::collect_timing). The code paths are templates on kTiming, so an
// untimed Detect contains no clock read and no timing branch in its inner loops.
using Clock = std::chrono::steady_clock;

long Nanoseconds(Clock::time_point from, Clock::time_point to) {
  return static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(to - from).count());
}
long NanosecondsSince(Clock::time_point start) { return Nanoseconds(start, Clock::now()); }

// Adds the time from construction to destruction to *total_ns; nothing when kOn is false.
template <bool kOn>
class ScopedTime {
 public:
  explicit ScopedTime(long*) {}
};
template <>
class ScopedTime<true> {
 public:
  explicit ScopedTime(long* total_ns) : total_ns_(total_ns), start_(Clock::now()) {}
  ~ScopedTime() { *total_ns_ += NanosecondsSince(start_); }
  ScopedTime(const ScopedTime&) = delete;
  ScopedTime& operator=(const ScopedTime&) = delete;

 private:
  long* total_ns_;
  Clock::time_point start_;
};

}  // namespace

struct Detector::Impl {
  DetectorConfig config;
  std::vector<PatternRuntime> runtimes;
  std::array<std::vector<int>, kMaxLabels> patterns_by_key_label;
  double max_reach_mm = 0.0;

  // Per-frame buffers, reused.
  std::vector<int> by_x;          // blob indices, bucketed by x
  std::vector<int> bucket_start;  // bucket b holds by_x[bucket_start[b] .. bucket_start[b + 1])
  std::vector<int> bucket_fill;
  double bucket_min_x = 0.0, bucket_width_mm = 1.0;
  std::vector<Candidate> candidates;
  std::vector<int> candidate_order;
  std::vector<char> used;
  DetectStats stats;
  // Timed Detect only: per-key stage times, summed over the frame's key candidates. Stages 4-7
  // are timed as one interval (fits_ns), colours inside it; correspondences = fits - colours.
  long neighbours_ns = 0, radial_sort_ns = 0, fits_ns = 0, colours_ns = 0;

  void Build();
  template <bool kTiming>
  void EvaluateKey(int p, int key, std::span<const Blob> blobs);
  void Finish(const Candidate& c, std::span<const Blob> blobs, Detection* d) const;
};

void Detector::Impl::Build() {
  const std::vector<std::string>& palette = config.palette;
  if (palette.empty() || static_cast<int>(palette.size()) > kMaxLabels) {
    throw InputError("palette has " + std::to_string(palette.size()) +
                     " colours; expected 1 to 64 colour names");
  }
  for (size_t i = 0; i < palette.size(); ++i) {
    if (palette[i].empty())
      throw InputError("palette colour " + std::to_string(i) + " is empty; expected a colour name");
    for (size_t j = 0; j < i; ++j) {
      if (palette[i] == palette[j]) {
        throw InputError("palette colour \"" + palette[i] +
                         "\" is listed twice; expected distinct colour names");
      }
    }
  }
  if (auto problem = ValidateDetectorOptions(config.options)) throw InputError(problem->message);
  if (config.patterns.empty()) throw InputError("no patterns; expected at least one pattern");
  const DetectorOptions& o = config.options;
  auto label_of = [&](const std::string& name) {
    const auto it = std::find(palette.begin(), palette.end(), name);
    return it == palette.end() ? -1 : static_cast<int>(it - palette.begin());
  };
  for (int p = 0; p < static_cast<int>(config.patterns.size()); ++p) {
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
      const int label = label_of(name);
      if (label < 0) {
        throw InputError(where + "key colour \"" + name + "\" is not in the palette");
      }
      patterns_by_key_label[label].push_back(p);
    }
    const Symmetry symmetry = FindSymmetry(pattern, dp.symmetry_tolerance_mm);
    for (int j = 0; j < rt.mk; ++j) rt.circ_patch[j] = symmetry.circular_order[j];

    // Codebook: colours in the palette, one colour per ID slot, a dense lookup table.
    const Codebook& book = dp.codebook;
    const std::vector<int> slots = IdSlots(pattern);
    if (book.num_slots != static_cast<int>(slots.size())) {
      throw InputError(where + "codebook has " + std::to_string(book.num_slots) +
                       " slots; expected " + std::to_string(slots.size()) + " (its ID slots)");
    }
    rt.codebook_colour.fill(-1);
    rt.num_codebook_colours = static_cast<int>(book.colours.size());
    for (int c = 0; c < rt.num_codebook_colours; ++c) {
      const int label = label_of(book.colours[c]);
      if (label < 0) {
        throw InputError(where + "codebook colour \"" + book.colours[c] +
                         "\" is not in the palette");
      }
      rt.codebook_colour[label] = static_cast<int8_t>(c);
      rt.neighbour_mask |= uint64_t{1} << label;
    }
    int64_t table_size = 1;
    for (size_t s = 0; s < slots.size(); ++s) {
      table_size *= std::max(1, rt.num_codebook_colours);
      if (table_size > (int64_t{1} << 22)) {
        throw InputError(where +
                         "codebook has too many colourings for the lookup table; "
                         "expected colours^slots <= 2^22");
      }
    }
    rt.code_to_id.assign(table_size, -1);
    for (const CodebookEntry& e : book.entries) {
      int64_t code = 0;
      for (int c : e.colour) code = code * rt.num_codebook_colours + c;
      rt.code_to_id[code] = e.id;
    }
    for (int j = 0; j < rt.mk; ++j) {
      const Patch& patch = pattern.patches[rt.circ_patch[j]];
      if (patch.role == PatchRole::kFixed) {
        rt.fixed_label[j] = label_of(patch.colour);
        if (rt.fixed_label[j] < 0) {
          throw InputError(where + "fixed patch colour \"" + patch.colour +
                           "\" is not in the palette");
        }
        rt.neighbour_mask |= uint64_t{1} << rt.fixed_label[j];
        rt.slot_weight[j] = 0;
      } else {
        rt.fixed_label[j] = kFixedAny;
        const int slot = static_cast<int>(std::find(slots.begin(), slots.end(), rt.circ_patch[j]) -
                                          slots.begin());
        int weight = 1;
        for (int s = slot + 1; s < static_cast<int>(slots.size()); ++s) {
          weight *= rt.num_codebook_colours;
        }
        rt.slot_weight[j] = weight;
      }
    }

    // Geometry: centred model positions for the full fit and each one-missing fit.
    const Vec2 key = pattern.patches[rt.key_index].position_mm;
    for (int variant = 0; variant <= rt.mk; ++variant) {
      const int skip = variant - 1;  // circular position left out, or -1
      Vec2 centroid = key;
      int count = 1;
      for (int j = 0; j < rt.mk; ++j) {
        if (j == skip) continue;
        centroid += pattern.patches[rt.circ_patch[j]].position_mm;
        ++count;
      }
      centroid /= count;
      rt.key_centred[variant] = key - centroid;
      rt.sq[variant] = rt.key_centred[variant].squaredNorm();
      for (int j = 0; j < rt.mk; ++j) {
        rt.circ_centred[variant][j] = pattern.patches[rt.circ_patch[j]].position_mm - centroid;
        if (j != skip) rt.sq[variant] += rt.circ_centred[variant][j].squaredNorm();
      }
    }
    // Paper section III: an n-patch rigid fit leaves 2n - 3 degrees of freedom of residual.
    const double sigma2 = o.patch_sigma_mm * o.patch_sigma_mm;
    rt.dof_full = 2 * rt.m - 3;
    rt.e_max_full = sigma2 * ChiSquaredQuantile(rt.dof_full, o.geometry_confidence);
    rt.dof_missing = 2 * (rt.m - 1) - 3;
    rt.can_fit_missing = o.missing_patch == MissingPatchPolicy::kFit && rt.dof_missing >= 1;
    if (rt.can_fit_missing) {
      rt.e_max_missing = sigma2 * ChiSquaredQuantile(rt.dof_missing, o.geometry_confidence);
    }

    // Areas and reach.
    const double key_area = std::numbers::pi * std::pow(pattern.patches[rt.key_index].radius_mm, 2);
    rt.key_area_min = o.area_ratio_min * key_area;
    rt.key_area_max = o.area_ratio_max * key_area;
    rt.nb_area_min = 1e300;
    rt.nb_area_max = 0.0;
    rt.ring_min_mm = 1e300;
    rt.ring_max_mm = 0.0;
    for (int j = 0; j < rt.mk; ++j) {
      const Patch& patch = pattern.patches[rt.circ_patch[j]];
      const double area = std::numbers::pi * patch.radius_mm * patch.radius_mm;
      rt.nb_area_min = std::min(rt.nb_area_min, o.area_ratio_min * area);
      rt.nb_area_max = std::max(rt.nb_area_max, o.area_ratio_max * area);
      const double r = (patch.position_mm - key).norm();
      rt.ring_min_mm = std::min(rt.ring_min_mm, r);
      rt.ring_max_mm = std::max(rt.ring_max_mm, r);
    }
    const double inner = std::max(0.0, rt.ring_min_mm - o.reach_margin_mm);
    rt.reach_min2 = inner * inner;
    rt.reach_max_mm = rt.ring_max_mm + o.reach_margin_mm;
    rt.reach_max2 = rt.reach_max_mm * rt.reach_max_mm;
    max_reach_mm = std::max(max_reach_mm, rt.reach_max_mm);

    rt.model = estimate::Model::FromPattern(pattern);
    if (rt.can_fit_missing) {
      for (int i = 0; i < rt.m; ++i) {
        if (i != rt.key_index) {
          rt.missing_model[i] = estimate::Model::FromPattern(WithoutPatch(pattern, i));
        }
      }
    }
    runtimes.push_back(std::move(rt));
  }
}

Detector::Detector(DetectorConfig config) : impl_(std::make_unique<Impl>()) {
  impl_->config = std::move(config);
  impl_->Build();
}
Detector::~Detector() = default;
Detector::Detector(Detector&&) noexcept = default;
Detector& Detector::operator=(Detector&&) noexcept = default;

const DetectorConfig& Detector::config() const { return impl_->config; }

int Detector::ColourLabel(std::string_view name) const {
  const auto& palette = impl_->config.palette;
  const auto it = std::find(palette.begin(), palette.end(), name);
  return it == palette.end() ? -1 : static_cast<int>(it - palette.begin());
}

double Detector::ResidualTolerance(int pattern, bool missing_patch) const {
  const PatternRuntime& rt = impl_->runtimes.at(pattern);
  return missing_patch ? rt.e_max_missing : rt.e_max_full;
}

namespace {

// The result of every rotation of one choice of neighbours.
struct SubsetVerdict {
  int ok = 0;     // rotations passing geometry and fixed colours
  int valid = 0;  // ... whose colours are an ID
  double best_ok_e = 1e300;
  int best_ok_shift = 0, best_ok_skip = -1;
  double valid_e = 1e300;
  int valid_shift = 0, valid_skip = -1, valid_id = -1;
};

// Minimum sum-squared error of the rigid fit of model points q (centred) to observed points w
// (centred): E = sum|q|^2 + sum|w|^2 - 2 sqrt(A^2 + B^2), A = sum q.w, B = sum q x w
// (2-D Procrustes, Umeyama 1991); no trigonometry.
inline double FitError(double sq, double sw, double a, double b) {
  return std::max(0.0, sq + sw - 2.0 * std::sqrt(a * a + b * b));
}

}  // namespace

template <bool kTiming>
void Detector::Impl::EvaluateKey(int p, int key, std::span<const Blob> blobs) {
  Clock::time_point stage_start;
  if constexpr (kTiming) stage_start = Clock::now();
  // Ends the current stage: adds its time to *total_ns and starts the next.
  auto end_stage = [&](long* total_ns) {
    if constexpr (kTiming) {
      const Clock::time_point now = Clock::now();
      *total_ns += Nanoseconds(stage_start, now);
      stage_start = now;
    }
  };
  const PatternRuntime& rt = runtimes[p];
  const Vec2 k = blobs[key].position_mm;

  // Stage 2: neighbours in the ring around the key (x-sorted search).
  std::array<int, kMaxGathered> nb;
  std::array<double, kMaxGathered> nb_dev;
  int n = 0;
  const int num_buckets = static_cast<int>(bucket_start.size()) - 1;
  auto bucket_of = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - bucket_min_x) / bucket_width_mm)), 0,
                      num_buckets - 1);
  };
  const int first = bucket_of(k.x() - rt.reach_max_mm), last = bucket_of(k.x() + rt.reach_max_mm);
  for (int t = bucket_start[first]; t < bucket_start[last + 1]; ++t) {
    const int j = by_x[t];
    if (j == key) continue;
    const Blob& b = blobs[j];
    if (b.colour < 0 || b.colour >= kMaxLabels || !((rt.neighbour_mask >> b.colour) & 1)) continue;
    if (b.area_mm2 < rt.nb_area_min || b.area_mm2 > rt.nb_area_max) continue;
    const double d2 = (b.position_mm - k).squaredNorm();
    if (d2 < rt.reach_min2 || d2 > rt.reach_max2) continue;
    if (n == kMaxGathered) {
      ++stats.neighbours_cut;
      continue;
    }
    const double d = std::sqrt(d2);
    nb_dev[n] = d < rt.ring_min_mm ? rt.ring_min_mm - d : std::max(0.0, d - rt.ring_max_mm);
    nb[n++] = j;
  }
  stats.neighbours += n;
  const int max_nb = config.options.max_neighbours;
  if (n > max_nb) {
    // Keep the neighbours closest to the model's ring.
    std::array<int, kMaxGathered> order;
    for (int i = 0; i < n; ++i) order[i] = i;
    std::partial_sort(order.begin(), order.begin() + max_nb, order.begin() + n, [&](int a, int b) {
      return std::tie(nb_dev[a], nb[a]) < std::tie(nb_dev[b], nb[b]);
    });
    std::array<int, kMaxGathered> kept;
    for (int i = 0; i < max_nb; ++i) kept[i] = nb[order[i]];
    std::copy(kept.begin(), kept.begin() + max_nb, nb.begin());
    stats.neighbours_cut += n - max_nb;
    n = max_nb;
  }
  const int mk = rt.mk;
  const bool try_missing = rt.can_fit_missing && n >= mk - 1;
  end_stage(&neighbours_ns);
  if (n < mk && !try_missing) return;

  // Stage 3: radial sort (insertion sort: n <= 16).
  std::array<double, 16> angle;
  std::array<Vec2, 16> pos;
  std::array<int, 16> label;
  for (int i = 0; i < n; ++i) {
    const Vec2 d = blobs[nb[i]].position_mm - k;
    angle[i] = std::atan2(d.y(), d.x());
  }
  for (int i = 1; i < n; ++i) {
    const double a = angle[i];
    const int b = nb[i];
    int j = i - 1;
    for (; j >= 0 && (angle[j] > a || (angle[j] == a && nb[j] > b)); --j) {
      angle[j + 1] = angle[j];
      nb[j + 1] = nb[j];
    }
    angle[j + 1] = a;
    nb[j + 1] = b;
  }
  for (int i = 0; i < n; ++i) {
    pos[i] = blobs[nb[i]].position_mm;
    label[i] = blobs[nb[i]].colour;
  }
  end_stage(&radial_sort_ns);

  // Stages 4-7 over every choice of `r` neighbours (in angular order, so the circular order is
  // kept) and every rotation; `missing` fits leave out one model position.
  Candidate best;
  bool have_best = false;
  auto run = [&](bool missing) {
    const int r = missing ? mk - 1 : mk;
    if (n < r) return;
    const double e_max = missing ? rt.e_max_missing : rt.e_max_full;
    std::array<int, 16> pick;
    for (int i = 0; i < r; ++i) pick[i] = i;
    bool found_valid = false;
    Candidate ambiguous;
    bool have_ambiguous = false;
    while (true) {
      // Observed centroid and centred points of this choice.
      Vec2 centroid = k;
      for (int i = 0; i < r; ++i) centroid += pos[pick[i]];
      centroid /= (r + 1);
      std::array<Vec2, 16> w;
      const Vec2 wk = k - centroid;
      double sw = wk.squaredNorm();
      for (int i = 0; i < r; ++i) {
        w[i] = pos[pick[i]] - centroid;
        sw += w[i].squaredNorm();
      }
      SubsetVerdict v;
      const int variants = missing ? mk : 1;
      for (int variant = 0; variant < variants; ++variant) {
        const int skip = missing ? variant : -1;
        const int vi = skip + 1;
        const auto& q = rt.circ_centred[vi];
        const Vec2& qk = rt.key_centred[vi];
        for (int shift = 0; shift < r; ++shift) {
          ++stats.correspondences;
          double a = qk.dot(wk), b = qk.x() * wk.y() - qk.y() * wk.x();
          for (int i = 0; i < r; ++i) {
            const int c = missing ? (skip + 1 + (i + shift) % r) % mk : (i + shift) % mk;
            a += q[c].dot(w[i]);
            b += q[c].x() * w[i].y() - q[c].y() * w[i].x();
          }
          const double e = FitError(rt.sq[vi], sw, a, b);
          if (e > e_max) continue;
          ++stats.geometry_passed;
          ScopedTime<kTiming> colour_time(&colours_ns);
          // Colours: fixed patches must match; ID slots form the code.
          bool colours_ok = true;
          int code = 0;
          bool code_ok = true;
          for (int i = 0; i < r && colours_ok; ++i) {
            const int c = missing ? (skip + 1 + (i + shift) % r) % mk : (i + shift) % mk;
            if (rt.fixed_label[c] != kFixedAny) {
              colours_ok = label[pick[i]] == rt.fixed_label[c];
            } else {
              const int cb = rt.codebook_colour[label[pick[i]]];
              if (cb < 0)
                code_ok = false;
              else
                code += cb * rt.slot_weight[c];
            }
          }
          if (!colours_ok) continue;
          int id = -1;
          bool has_id = false;
          if (code_ok) {
            if (skip >= 0 && rt.fixed_label[skip] == kFixedAny) {
              // The missing ID slot's colour is unknown: the ID is known only if exactly one
              // completion is in the codebook.
              int found = 0;
              for (int c = 0; c < rt.num_codebook_colours; ++c) {
                const int cid = rt.code_to_id[code + c * rt.slot_weight[skip]];
                if (cid >= 0) {
                  id = cid;
                  ++found;
                }
              }
              has_id = found > 0;
              if (found > 1) id = -1;
            } else {
              id = rt.code_to_id[code];
              has_id = id >= 0;
            }
          }
          ++v.ok;
          if (e < v.best_ok_e) {
            v.best_ok_e = e;
            v.best_ok_shift = shift;
            v.best_ok_skip = skip;
          }
          if (has_id) {
            ++v.valid;
            if (e < v.valid_e) {
              v.valid_e = e;
              v.valid_shift = shift;
              v.valid_skip = skip;
              v.valid_id = id;
            }
          }
        }
      }
      // Stage 6 verdict for this choice of neighbours (nothing to decide when no rotation
      // passed geometry and fixed colours).
      if (v.ok > 0) {
        ScopedTime<kTiming> colour_time(&colours_ns);
        const bool single = v.valid == 1;
        const bool amb = !single && v.ok >= 2;
        if (v.ok == 1 && v.valid == 0) ++stats.colour_rejected;
        if (single || amb) {
          Candidate c;
          c.pattern = p;
          c.key_blob = key;
          c.e = single ? v.valid_e : v.best_ok_e;
          c.score = c.e / e_max;
          c.id = single ? v.valid_id : -1;
          const int shift = single ? v.valid_shift : v.best_ok_shift;
          const int skip = single ? v.valid_skip : v.best_ok_skip;
          c.status = amb ? DetectionStatus::kAmbiguous
                         : (missing ? DetectionStatus::kMissingPatch : DetectionStatus::kOk);
          c.missing_patch = skip >= 0 ? rt.circ_patch[skip] : -1;
          c.blob.fill(-1);
          c.blob[rt.key_index] = key;
          c.num_blobs = r + 1;
          for (int i = 0; i < r; ++i) {
            const int pc = missing ? (skip + 1 + (i + shift) % r) % mk : (i + shift) % mk;
            c.blob[rt.circ_patch[pc]] = nb[pick[i]];
          }
          if (single) {
            if (!found_valid || c.e < best.e) best = c;
            found_valid = true;
          } else if (!have_ambiguous || c.e < ambiguous.e) {
            ambiguous = c;
            have_ambiguous = true;
          }
        }
      }
      // Next combination of r out of n, in lexicographic order.
      int i = r - 1;
      while (i >= 0 && pick[i] == n - r + i) --i;
      if (i < 0) break;
      ++pick[i];
      for (int j = i + 1; j < r; ++j) pick[j] = pick[j - 1] + 1;
    }
    if (found_valid) {
      have_best = true;
    } else if (have_ambiguous) {
      best = ambiguous;
      have_best = true;
    }
  };
  run(false);
  if (!have_best && try_missing) run(true);
  end_stage(&fits_ns);
  if (have_best) candidates.push_back(best);
}

void Detector::Impl::Finish(const Candidate& c, std::span<const Blob> blobs, Detection* d) const {
  const PatternRuntime& rt = runtimes[c.pattern];
  d->pattern = c.pattern;
  d->team_colour = blobs[c.key_blob].colour;
  d->id = c.id;
  d->status = c.status;
  d->residual_mm2 = c.e;
  d->missing_patch = c.missing_patch;
  d->blob = c.blob;
  const bool missing = c.missing_patch >= 0;
  const estimate::Model& model = missing ? rt.missing_model[c.missing_patch] : rt.model;
  std::array<Vec2, kMaxPatches> observed;
  int count = 0;
  for (int i = 0; i < rt.m; ++i) {
    if (i != c.missing_patch) observed[count++] = blobs[c.blob[i]].position_mm;
  }
  switch (config.options.estimator) {
    case estimate::Estimator::kFast:
      d->pose = estimate::Fast(model, observed.data());
      break;
    case estimate::Estimator::kLsq:
      d->pose = estimate::LeastSquares(model, observed.data());
      break;
    case estimate::Estimator::kKey:
      d->pose = estimate::KeyPatch(model, observed.data());
      break;
    case estimate::Estimator::kMl:
      d->pose = estimate::MaximumLikelihood(model, observed.data(),
                                            estimate::Fast(model, observed.data()),
                                            config.options.ml, nullptr);
      break;
  }
  const int dof = missing ? rt.dof_missing : rt.dof_full;
  const double sigma2 = config.options.patch_sigma_mm * config.options.patch_sigma_mm;
  d->confidence = ChiSquaredSurvival(dof, c.e / sigma2);
}

namespace {
// Blobs farther than this from the origin (or not finite) are ignored: no field is 1000 km wide,
// and it keeps the bucket arithmetic finite.
bool Usable(const Blob& b) {
  constexpr double kMaxCoordinateMm = 1e9;
  return std::abs(b.position_mm.x()) <= kMaxCoordinateMm &&
         std::abs(b.position_mm.y()) <= kMaxCoordinateMm;
}
}  // namespace

void Detector::Detect(std::span<const Blob> blobs, std::vector<Detection>* detections,
                      DetectStats* stats) {
  Impl& s = *impl_;
  const bool timing = stats != nullptr && stats->collect_timing;
  Clock::time_point start;
  if (timing) {
    start = Clock::now();
    s.neighbours_ns = s.radial_sort_ns = s.fits_ns = s.colours_ns = 0;
  }
  s.stats = DetectStats{};
  s.candidates.clear();
  detections->clear();
  const int n = static_cast<int>(blobs.size());

  // Blobs bucketed by x (counting sort; buckets one reach wide) for the neighbour search of
  // stage 2. Unusable blobs (non-finite, absurdly far) are left out.
  double min_x = 1e300, max_x = -1e300;
  for (const Blob& b : blobs) {
    if (!Usable(b)) continue;
    min_x = std::min(min_x, b.position_mm.x());
    max_x = std::max(max_x, b.position_mm.x());
  }
  constexpr int kMaxBuckets = 4096;
  s.bucket_min_x = min_x <= max_x ? min_x : 0.0;
  const double range = min_x <= max_x ? max_x - min_x : 0.0;
  s.bucket_width_mm = std::max(s.max_reach_mm, range / (kMaxBuckets - 1));
  const int num_buckets = static_cast<int>(range / s.bucket_width_mm) + 1;
  s.bucket_start.assign(num_buckets + 1, 0);
  s.by_x.resize(n);
  auto bucket_of = [&](const Blob& b) {
    return std::min(num_buckets - 1,
                    static_cast<int>((b.position_mm.x() - s.bucket_min_x) / s.bucket_width_mm));
  };
  for (const Blob& b : blobs) {
    if (Usable(b)) ++s.bucket_start[bucket_of(b) + 1];
  }
  for (int b = 0; b < num_buckets; ++b) s.bucket_start[b + 1] += s.bucket_start[b];
  s.bucket_fill.assign(num_buckets, 0);
  for (int i = 0; i < n; ++i) {
    if (!Usable(blobs[i])) continue;
    const int b = bucket_of(blobs[i]);
    s.by_x[s.bucket_start[b] + s.bucket_fill[b]++] = i;
  }

  // Stage 1: key candidates; stages 2-7 per candidate.
  for (int i = 0; i < n; ++i) {
    const int label = blobs[i].colour;
    if (label < 0 || label >= kMaxLabels || !Usable(blobs[i])) continue;
    for (int p : s.patterns_by_key_label[label]) {
      const PatternRuntime& rt = s.runtimes[p];
      if (blobs[i].area_mm2 < rt.key_area_min || blobs[i].area_mm2 > rt.key_area_max) continue;
      ++s.stats.key_candidates;
      if (timing)
        s.EvaluateKey<true>(p, i, blobs);
      else
        s.EvaluateKey<false>(p, i, blobs);
    }
  }
  long keys_ns = 0, pose_ns = 0;
  Clock::time_point conflicts_start;
  if (timing) {
    conflicts_start = Clock::now();
    keys_ns = Nanoseconds(start, conflicts_start);
  }

  // Stage 8: each blob goes to the best-fitting candidate that claims it.
  const int nc = static_cast<int>(s.candidates.size());
  s.candidate_order.resize(nc);
  for (int i = 0; i < nc; ++i) s.candidate_order[i] = i;
  // Order: unambiguous first; then the candidate explaining more blobs (a larger pattern that
  // fits within tolerance is the more specific explanation, e.g. ssl-standard over a Simple
  // pattern keyed by the same colour, and a full fit over a missing-patch fit); then the
  // better fit relative to its tolerance.
  std::sort(s.candidate_order.begin(), s.candidate_order.end(), [&](int a, int b) {
    const Candidate& ca = s.candidates[a];
    const Candidate& cb = s.candidates[b];
    const bool amb_a = ca.status == DetectionStatus::kAmbiguous;
    const bool amb_b = cb.status == DetectionStatus::kAmbiguous;
    const int fewer_a = -ca.num_blobs, fewer_b = -cb.num_blobs;
    return std::tie(amb_a, fewer_a, ca.score, ca.key_blob, ca.pattern) <
           std::tie(amb_b, fewer_b, cb.score, cb.key_blob, cb.pattern);
  });
  s.used.assign(n, 0);
  for (int ci : s.candidate_order) {
    const Candidate& c = s.candidates[ci];
    const int m = s.runtimes[c.pattern].m;
    bool free = true;
    for (int i = 0; i < m && free; ++i) free = c.blob[i] < 0 || !s.used[c.blob[i]];
    if (!free) {
      ++s.stats.conflicts;
      continue;
    }
    for (int i = 0; i < m; ++i) {
      if (c.blob[i] >= 0) s.used[c.blob[i]] = 1;
    }
    // Stage 9: pose and confidence.
    detections->emplace_back();
    if (timing) {
      const Clock::time_point pose_start = Clock::now();
      s.Finish(c, blobs, &detections->back());
      pose_ns += NanosecondsSince(pose_start);
    } else {
      s.Finish(c, blobs, &detections->back());
    }
    if (c.status == DetectionStatus::kAmbiguous) ++s.stats.ambiguous;
    if (c.status == DetectionStatus::kMissingPatch) ++s.stats.missing_fits;
  }
  Clock::time_point order_start;
  if (timing) order_start = Clock::now();
  std::sort(detections->begin(), detections->end(), [](const Detection& a, const Detection& b) {
    return std::tie(a.pattern, a.team_colour, a.status, a.id, a.pose.x_mm, a.pose.y_mm) <
           std::tie(b.pattern, b.team_colour, b.status, b.id, b.pose.x_mm, b.pose.y_mm);
  });
  s.stats.detections = static_cast<long>(detections->size());
  if (timing) {
    // The stages partition [start, end]: stage 1 is the key loop less the per-key stages 2-7,
    // stage 8 the conflict pass less the poses in it, stage 9 the poses and the final order.
    const Clock::time_point end = Clock::now();
    DetectStageTimes& t = s.stats.time;
    t.neighbours_ns = s.neighbours_ns;
    t.radial_sort_ns = s.radial_sort_ns;
    t.correspondences_ns = s.fits_ns - s.colours_ns;
    t.colours_ns = s.colours_ns;
    t.key_candidates_ns = keys_ns - s.neighbours_ns - s.radial_sort_ns - s.fits_ns;
    t.conflicts_ns = Nanoseconds(conflicts_start, order_start) - pose_ns;
    t.pose_ns = pose_ns + Nanoseconds(order_start, end);
    t.total_ns = Nanoseconds(start, end);
    s.stats.collect_timing = true;
  }
  if (stats != nullptr) *stats = s.stats;
}

}  // namespace patlab::detect

// DiagnoseKeys (key_diagnosis.h): the measures of the stage that rejected a key candidate, the
// candidate setting changes computed from them, and the cheapest one that Detect confirms.
#include "patlab/detect/key_diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::detect {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// What stages 1-2 of pattern p test, from the configuration as the Detector builds it
// (detector_build.cpp BuildTolerancesAndReach).
struct PatternFacts {
  int m = 0, mk = 0, needed = 0;  // patches, non-key patches, neighbours a fit needs
  double key_area = 0.0;
  double nb_area_lo = kInf, nb_area_hi = 0.0;  // smallest and largest non-key patch area
  double ring_min = kInf, ring_max = 0.0;      // non-key patches' distances from the key
  std::vector<bool> neighbour_colour;          // per palette label
};

int LabelOf(const DetectorConfig& config, const std::string& name) {
  const auto it = std::find(config.palette.begin(), config.palette.end(), name);
  return it == config.palette.end() ? -1 : static_cast<int>(it - config.palette.begin());
}

PatternFacts FactsOf(const DetectorConfig& config, int p) {
  const DetectorPattern& dp = config.patterns[static_cast<size_t>(p)];
  const Pattern& pattern = dp.pattern;
  PatternFacts f;
  f.m = pattern.size();
  f.mk = f.m - 1;
  const bool fit_missing =
      config.options.missing_patch == MissingPatchPolicy::kFit && 2 * (f.m - 1) - 3 >= 1;
  f.needed = fit_missing ? f.mk - 1 : f.mk;
  const Patch& key = pattern.patches[static_cast<size_t>(pattern.key_index)];
  f.key_area = key.Area();
  f.neighbour_colour.assign(config.palette.size(), false);
  for (const std::string& c : dp.codebook.colours) {
    const int label = LabelOf(config, c);
    if (label >= 0) f.neighbour_colour[static_cast<size_t>(label)] = true;
  }
  for (int i = 0; i < f.m; ++i) {
    if (i == pattern.key_index) continue;
    const Patch& patch = pattern.patches[static_cast<size_t>(i)];
    f.nb_area_lo = std::min(f.nb_area_lo, patch.Area());
    f.nb_area_hi = std::max(f.nb_area_hi, patch.Area());
    const double r = (patch.position_mm - key.position_mm).norm();
    f.ring_min = std::min(f.ring_min, r);
    f.ring_max = std::max(f.ring_max, r);
    if (patch.role == PatchRole::kFixed) {
      const int label = LabelOf(config, patch.colour);
      if (label >= 0) f.neighbour_colour[static_cast<size_t>(label)] = true;
    }
  }
  return f;
}

std::string ColourName(const DetectorConfig& config, int label) {
  return label >= 0 && label < static_cast<int>(config.palette.size())
             ? config.palette[static_cast<size_t>(label)]
             : "?";
}

// Stage 2's tests of blob j around the key at key_mm.
WouldBeNeighbour TestNeighbour(const DetectorConfig& config, const PatternFacts& f,
                               std::span<const Blob> blobs, const Vec2& key_mm, int j) {
  const DetectorOptions& o = config.options;
  const Blob& b = blobs[static_cast<size_t>(j)];
  WouldBeNeighbour w;
  w.blob = j;
  w.distance_mm = (b.position_mm - key_mm).norm();
  w.reach_min_mm = std::max(0.0, f.ring_min - o.reach_margin_mm);
  w.reach_max_mm = f.ring_max + o.reach_margin_mm;
  w.area_ratio = b.area_mm2 / f.nb_area_lo;
  w.area_ratio_min = o.area_ratio_min;
  w.area_ratio_max = o.area_ratio_max * f.nb_area_hi / f.nb_area_lo;
  w.colour_ok = b.colour >= 0 && b.colour < static_cast<int>(f.neighbour_colour.size()) &&
                f.neighbour_colour[static_cast<size_t>(b.colour)];
  const double d2 = (b.position_mm - key_mm).squaredNorm();
  w.reach_ok = d2 >= w.reach_min_mm * w.reach_min_mm && d2 <= w.reach_max_mm * w.reach_max_mm;
  w.area_ok = b.area_mm2 >= o.area_ratio_min * f.nb_area_lo &&
              b.area_mm2 <= o.area_ratio_max * f.nb_area_hi;
  return w;
}

// How far a distance lies outside the model's ring (0 inside it).
double RingDeviation(const PatternFacts& f, double d) {
  return d < f.ring_min ? f.ring_min - d : std::max(0.0, d - f.ring_max);
}

// The blobs near the key that stage 2 did not count, nearest the ring first.
std::vector<WouldBeNeighbour> NearBlobs(const DetectorConfig& config, const PatternFacts& f,
                                        std::span<const Blob> blobs, int key) {
  const Vec2 key_mm = blobs[static_cast<size_t>(key)].position_mm;
  const double limit = f.ring_max + std::max(f.ring_max, 2.0 * config.options.reach_margin_mm);
  std::vector<WouldBeNeighbour> out;
  for (int j = 0; j < static_cast<int>(blobs.size()); ++j) {
    if (j == key || !((blobs[static_cast<size_t>(j)].position_mm - key_mm).norm() <= limit)) {
      continue;
    }
    WouldBeNeighbour w = TestNeighbour(config, f, blobs, key_mm, j);
    if (!(w.colour_ok && w.reach_ok && w.area_ok)) out.push_back(w);
  }
  std::sort(out.begin(), out.end(), [&f](const WouldBeNeighbour& a, const WouldBeNeighbour& b) {
    return std::make_tuple(!a.colour_ok, RingDeviation(f, a.distance_mm), a.blob) <
           std::make_tuple(!b.colour_ok, RingDeviation(f, b.distance_mm), b.blob);
  });
  return out;
}

// value rounded to 3 significant digits away from the bound it must pass (up or down), so the
// rounded value still admits it: never the value itself rounded the wrong way.
double Round3(double value, bool up) {
  if (!(value > 0.0) || !std::isfinite(value)) return value;
  const int exponent = static_cast<int>(std::floor(std::log10(value))) - 2;
  const double power = std::pow(10.0, std::abs(exponent));
  const auto at = [&](double digits) { return exponent < 0 ? digits / power : digits * power; };
  const double q = exponent < 0 ? value * power : value / power;
  double digits = up ? std::ceil(q - 1e-9) : std::floor(q + 1e-9);
  if (up && at(digits) < value) digits += 1.0;
  if (!up && at(digits) > value) digits -= 1.0;
  return at(digits);
}

struct Candidate {
  SettingChange change;
  double cost = 0.0;
};

double Cost(const SettingChange& c) {
  if (c.key == "geometry_confidence") return std::fabs(std::log((1.0 - c.to) / (1.0 - c.from)));
  if (!(c.from > 0.0)) return 10.0 + c.to;
  return std::fabs(std::log(c.to / c.from));
}

void Add(std::vector<Candidate>* out, const std::string& key, double from, double to) {
  if (!std::isfinite(to) || to == from) return;
  const SettingChange c{key, from, to};
  out->push_back({c, Cost(c)});
}

// Candidates from the blobs stage 2 left out: each blob stopped by one test alone brings the
// value of that setting which lets it in.
void NeighbourCandidates(const DetectorConfig& config, const PatternFacts& f,
                         const std::vector<WouldBeNeighbour>& near, double scale,
                         std::vector<Candidate>* out) {
  const DetectorOptions& o = config.options;
  for (const WouldBeNeighbour& w : near) {
    if (!w.colour_ok) continue;
    if (w.area_ok && !w.reach_ok) {
      Add(out, "reach_margin_mm", o.reach_margin_mm, Round3(RingDeviation(f, w.distance_mm), true));
    }
    if (w.reach_ok && !w.area_ok && w.area_ratio < o.area_ratio_min) {
      Add(out, "area_ratio_min", o.area_ratio_min / scale, Round3(w.area_ratio / scale, false));
    }
    if (w.reach_ok && !w.area_ok && w.area_ratio >= o.area_ratio_min) {
      const double ratio_max = w.area_ratio * f.nb_area_lo / f.nb_area_hi;
      Add(out, "area_ratio_max", o.area_ratio_max, Round3(ratio_max, true));
    }
  }
}

// Candidates from the nearest rotation's E against the tolerance (stage 4): the patch_sigma_mm
// and the geometry_confidence whose tolerance admits it.
void GeometryCandidates(const DetectorConfig& config, const KeyExplanation& e, int m,
                        std::vector<Candidate>* out) {
  const DetectorOptions& o = config.options;
  if (!std::isfinite(e.best_e_mm2) || e.best_e_mm2 <= e.tolerance_mm2) return;
  const double sigma2 = EffectiveSigma2Mm2(o);
  const double quantile = e.tolerance_mm2 / sigma2;
  const double c2 = o.calibration_residual_mm * o.calibration_residual_mm;
  Add(out, "patch_sigma_mm", o.patch_sigma_mm,
      Round3(std::sqrt(e.best_e_mm2 / quantile - c2), true));
  const double miss = ChiSquaredSurvival(2 * m - 3, e.best_e_mm2 / sigma2);
  if (miss > 1e-12) {
    Add(out, "geometry_confidence", o.geometry_confidence, 1.0 - Round3(miss, false));
  }
}

// Every candidate change for record e, cheapest first.
std::vector<Candidate> Candidates(const DetectorConfig& config, std::span<const Blob> blobs,
                                  const KeyExplanation& e, const PatternFacts& f,
                                  const std::vector<WouldBeNeighbour>& near, double scale) {
  const DetectorOptions& o = config.options;
  std::vector<Candidate> out;
  if (e.outcome == KeyOutcome::kKeyArea) {
    const double ratio = blobs[static_cast<size_t>(e.key_blob)].area_mm2 / f.key_area;
    if (ratio < o.area_ratio_min) {
      Add(&out, "area_ratio_min", o.area_ratio_min / scale, Round3(ratio / scale, false));
    } else {
      Add(&out, "area_ratio_max", o.area_ratio_max, Round3(ratio, true));
    }
  } else {
    NeighbourCandidates(config, f, near, scale, &out);
    GeometryCandidates(config, e, f.m, &out);
    int within = 0;  // neighbours passing stage 2's tests before the max_neighbours cut
    const Vec2 key_mm = blobs[static_cast<size_t>(e.key_blob)].position_mm;
    for (int j = 0; j < static_cast<int>(blobs.size()); ++j) {
      const WouldBeNeighbour w = TestNeighbour(config, f, blobs, key_mm, j);
      within += static_cast<int>(j != e.key_blob && w.colour_ok && w.reach_ok && w.area_ok);
    }
    for (int n = o.max_neighbours + 1; n <= std::min(within, 16); ++n) {
      Add(&out, "max_neighbours", o.max_neighbours, n);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.cost, a.change.key, a.change.to) <
           std::tie(b.cost, b.change.key, b.change.to);
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Candidate& a, const Candidate& b) {
                          return a.change.key == b.change.key && a.change.to == b.change.to;
                        }),
            out.end());
  return out;
}

// The nearest rotation's colours against the codebook and the fixed colours (kColours).
void DiagnoseColours(const DetectorConfig& config, std::span<const Blob> blobs, KeyDiagnosis* d) {
  const KeyExplanation& e = d->explanation;
  const DetectorPattern& dp = config.patterns[static_cast<size_t>(e.pattern)];
  const Pattern& pattern = dp.pattern;
  if (e.nearest_rotation < 0) return;
  std::vector<int> code;  // codebook colour per ID slot, -1 when none
  std::string wrong;
  for (int i = 0; i < pattern.size(); ++i) {
    const int b = e.nearest_blob[static_cast<size_t>(i)];
    const std::string name = b >= 0 ? ColourName(config, blobs[static_cast<size_t>(b)].colour) : "";
    d->patch_colours.push_back(name);
    const Patch& patch = pattern.patches[static_cast<size_t>(i)];
    if (patch.role == PatchRole::kFixed && name != patch.colour && wrong.empty()) {
      wrong =
          "patch " + std::to_string(i) + " is " + name + ", its fixed colour is " + patch.colour;
    }
    if (patch.role != PatchRole::kId) continue;
    const auto it = std::find(dp.codebook.colours.begin(), dp.codebook.colours.end(), name);
    code.push_back(
        it == dp.codebook.colours.end() ? -1 : static_cast<int>(it - dp.codebook.colours.begin()));
    if (code.back() < 0 && wrong.empty()) {
      std::string expected;
      for (const std::string& c : dp.codebook.colours)
        expected.append(expected.empty() ? "" : "|").append(c);
      wrong = "patch " + std::to_string(i) + " is " + name + ", no ID colour (" + expected + ")";
    }
  }
  const std::vector<int> slots = IdSlots(pattern);
  int best = static_cast<int>(slots.size()) + 1;
  for (const CodebookEntry& entry : dp.codebook.entries) {
    std::vector<int> differs;
    for (size_t s = 0; s < slots.size(); ++s) {
      if (entry.colour[s] != code[s]) differs.push_back(slots[s]);
    }
    if (static_cast<int>(differs.size()) < best) {
      best = static_cast<int>(differs.size());
      d->nearest_id = entry.id;
      d->nearest_id_differs = differs;
    }
  }
  d->colour_problem = wrong.empty() ? "the ID patches' colours are no ID of the codebook" : wrong;
}

// How far record e got: the stage reached, then the smaller E / tolerance.
std::tuple<int, double> Progress(const KeyExplanation& e) {
  int stage = 0;
  switch (e.outcome) {
    case KeyOutcome::kKeyArea:
      stage = 0;
      break;
    case KeyOutcome::kFewNeighbours:
      stage = 1;
      break;
    case KeyOutcome::kGeometry:
      stage = 2;
      break;
    case KeyOutcome::kColours:
      stage = 3;
      break;
    case KeyOutcome::kConflict:
      stage = 4;
      break;
    case KeyOutcome::kDetected:
      stage = 5;
      break;
  }
  const double ratio =
      std::isfinite(e.best_e_mm2) && e.tolerance_mm2 > 0.0 ? e.best_e_mm2 / e.tolerance_mm2 : kInf;
  return {-stage, ratio};
}

std::vector<StageMeasure> MeasuresOf(const DetectorConfig& config, std::span<const Blob> blobs,
                                     const KeyExplanation& e, const PatternFacts& f, double scale) {
  const DetectorOptions& o = config.options;
  switch (e.outcome) {
    case KeyOutcome::kKeyArea: {
      const double ratio = blobs[static_cast<size_t>(e.key_blob)].area_mm2 / f.key_area;
      const std::string note =
          scale == 1.0 ? ""
                       : "area_ratio_min " + FormatSignificant(o.area_ratio_min / scale, 3) +
                             " x edge-loss factor " + FormatSignificant(scale, 3);
      if (ratio < o.area_ratio_min) {
        return {{"key area ratio", ratio, "<", o.area_ratio_min, "", note}};
      }
      return {{"key area ratio", ratio, ">", o.area_ratio_max, "", ""}};
    }
    case KeyOutcome::kFewNeighbours:
      return {{"neighbours within reach", static_cast<double>(e.neighbours), "<",
               static_cast<double>(f.needed), "", ""}};
    case KeyOutcome::kGeometry:
      return {{"E", e.best_e_mm2, ">", e.tolerance_mm2, "mm^2", ""}};
    case KeyOutcome::kColours:
    case KeyOutcome::kDetected:
    case KeyOutcome::kConflict:
      if (!std::isfinite(e.best_e_mm2)) return {};
      return {{"E", e.best_e_mm2, "<=", e.tolerance_mm2, "mm^2", ""}};
  }
  return {};
}

// The cheapest candidate that Detect confirms, or why there is none.
void FindChange(const DetectorConfig& config, std::span<const Blob> blobs,
                const std::vector<Candidate>& candidates, const DiagnosisOptions& options,
                KeyDiagnosis* d) {
  const KeyExplanation& e = d->explanation;
  int checks = 0;
  for (const Candidate& c : candidates) {
    if (checks++ >= options.max_checks) break;
    const std::optional<Detection> accepted =
        DetectWithChange(config, blobs, e.pattern, e.key_blob, c.change, options);
    if (accepted) {
      d->change = c.change;
      d->accepted = *accepted;
      return;
    }
  }
  if (e.outcome == KeyOutcome::kConflict) {
    d->no_change = "no tolerance: key " + std::to_string(e.lost_to_key) + " (" +
                   config.patterns[static_cast<size_t>(e.lost_to_pattern)].pattern.name +
                   ") ranks first and took blob " + std::to_string(e.lost_blob);
  } else if (e.outcome == KeyOutcome::kColours) {
    d->no_change = "no tolerance: the colours decide (thresholds, ID colours, codebook)";
  } else if (candidates.empty()) {
    d->no_change = "no single tolerance change reaches it";
  } else {
    const size_t checked = std::min<size_t>(candidates.size(), options.max_checks);
    d->no_change = "none of the " + std::to_string(checked) +
                   " single changes checked accepts it (the cheapest: " +
                   SettingChangeText(candidates.front().change) + ")";
  }
}

}  // namespace

std::optional<Detection> DetectWithChange(const DetectorConfig& config, std::span<const Blob> blobs,
                                          int pattern, int key_blob, const SettingChange& change,
                                          const DiagnosisOptions& options) {
  DetectorConfig changed = config;
  DetectorOptions& o = changed.options;
  if (change.key == "area_ratio_min") {
    o.area_ratio_min = change.to * options.area_ratio_min_scale;
  } else if (change.key == "area_ratio_max") {
    o.area_ratio_max = change.to;
  } else if (change.key == "reach_margin_mm") {
    o.reach_margin_mm = change.to;
  } else if (change.key == "max_neighbours") {
    o.max_neighbours = static_cast<int>(change.to);
  } else if (change.key == "patch_sigma_mm") {
    o.patch_sigma_mm = change.to;
  } else if (change.key == "geometry_confidence") {
    o.geometry_confidence = change.to;
  } else {
    return std::nullopt;
  }
  std::vector<Detection> detections;
  std::vector<KeyExplanation> records;
  try {
    Detector detector(std::move(changed));
    detector.Detect(blobs, &detections, nullptr, nullptr, &records);
  } catch (const InputError&) {
    return std::nullopt;
  }
  for (const KeyExplanation& r : records) {
    if (r.pattern == pattern && r.key_blob == key_blob && r.outcome == KeyOutcome::kDetected &&
        r.detection >= 0) {
      return detections[static_cast<size_t>(r.detection)];
    }
  }
  return std::nullopt;
}

bool ChangeAccepts(const DetectorConfig& config, std::span<const Blob> blobs, int pattern,
                   int key_blob, const SettingChange& change, const DiagnosisOptions& options) {
  return DetectWithChange(config, blobs, pattern, key_blob, change, options).has_value();
}

std::vector<KeyDiagnosis> DiagnoseKeys(const DetectorConfig& config, std::span<const Blob> blobs,
                                       const std::vector<KeyExplanation>& explanations,
                                       const DiagnosisOptions& options) {
  std::vector<KeyDiagnosis> out;
  std::vector<PatternFacts> facts;
  for (int p = 0; p < static_cast<int>(config.patterns.size()); ++p) {
    facts.push_back(FactsOf(config, p));
  }
  for (const KeyExplanation& e : explanations) {
    KeyDiagnosis& d = out.emplace_back();
    d.explanation = e;
    const PatternFacts& f = facts[static_cast<size_t>(e.pattern)];
    d.measures = MeasuresOf(config, blobs, e, f, options.area_ratio_min_scale);
    if (e.outcome == KeyOutcome::kDetected) continue;
    std::vector<WouldBeNeighbour> near;
    if (e.outcome != KeyOutcome::kKeyArea) near = NearBlobs(config, f, blobs, e.key_blob);
    if (e.outcome == KeyOutcome::kFewNeighbours) {
      d.would_be.assign(near.begin(), near.begin() + std::min<long>(3, std::ssize(near)));
    }
    if (e.outcome == KeyOutcome::kColours) DiagnoseColours(config, blobs, &d);
    FindChange(config, blobs, Candidates(config, blobs, e, f, near, options.area_ratio_min_scale),
               options, &d);
  }
  // The nearest pattern of each key blob.
  for (size_t i = 0; i < out.size(); ++i) {
    size_t best = i;
    for (size_t j = 0; j < out.size(); ++j) {
      if (out[j].explanation.key_blob != out[i].explanation.key_blob) continue;
      if (std::tuple_cat(Progress(out[j].explanation), std::make_tuple(j)) <
          std::tuple_cat(Progress(out[best].explanation), std::make_tuple(best))) {
        best = j;
      }
    }
    out[i].nearest_pattern = best == i;
  }
  return out;
}

}  // namespace patlab::detect

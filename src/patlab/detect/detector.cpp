// The detector's public API and one frame: stage 1 (key candidates), then stages 2-6 per key
// (detector_stages.cpp), stage 7 (conflicts) and stage 8 (pose and output order). Construction is
// in detector_build.cpp.
#include "patlab/detect/detector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/detector_internal.h"
#include "patlab/estimate/robust.h"

namespace patlab::detect {

using internal::kMaxLabels;
using internal::PatternRuntime;
using internal::StageClock;

std::string_view MissingPatchPolicyName(MissingPatchPolicy policy) {
  return NameOf(policy, kMissingPatchPolicyNames);
}

std::string_view DetectionStatusName(DetectionStatus status) {
  return NameOf(status, kDetectionStatusNames);
}

DetectStats& DetectStats::operator+=(const DetectStats& o) {
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

std::vector<OptionsProblem> Check(const DetectorOptions& o) {
  OptionsChecker check;
  check.Positive("patch_sigma_mm", o.patch_sigma_mm, "mm")
      .InOpenRange("geometry_confidence", o.geometry_confidence, 0.0, 1.0, "a probability")
      .NonNegative("calibration_residual_mm", o.calibration_residual_mm, "mm")
      .NonNegative("reach_margin_mm", o.reach_margin_mm, "mm")
      .NonNegative("area_ratio_min", o.area_ratio_min)
      .Require("area_ratio_max", o.area_ratio_max,
               std::isfinite(o.area_ratio_max) && o.area_ratio_max > o.area_ratio_min,
               "a finite number > area_ratio_min (" + FormatNumber(o.area_ratio_min) + ")")
      .IntegerInRange("max_neighbours", o.max_neighbours, 1, internal::kMaxNeighbours);
  std::vector<OptionsProblem> problems = check.Take();
  for (OptionsProblem& problem : estimate::Check(o.ml, "ml_")) {
    problems.push_back(std::move(problem));
  }
  return problems;
}

void Validate(const DetectorOptions& options) { ThrowFirstProblem(Check(options)); }

double EffectiveSigma2Mm2(const DetectorOptions& o) {
  return o.patch_sigma_mm * o.patch_sigma_mm +
         o.calibration_residual_mm * o.calibration_residual_mm;
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

// Blobs farther than this from the origin (or not finite) are ignored: no field is 1000 km wide,
// and it keeps the bucket arithmetic finite.
bool Usable(const Blob& b) {
  constexpr double kMaxCoordinateMm = 1e9;
  return std::abs(b.position_mm.x()) <= kMaxCoordinateMm &&
         std::abs(b.position_mm.y()) <= kMaxCoordinateMm;
}

// Stage 7's order: unambiguous first; then the candidate explaining more blobs (a larger pattern
// that fits within tolerance is the more specific explanation, e.g. ssl-standard over a Simple
// pattern keyed by the same colour, and a full fit over a missing-patch fit); then the better fit
// relative to its tolerance.
bool RanksBefore(const internal::Candidate& ca, const internal::Candidate& cb) {
  const bool amb_a = ca.status == DetectionStatus::kAmbiguous;
  const bool amb_b = cb.status == DetectionStatus::kAmbiguous;
  const int fewer_a = -ca.num_blobs, fewer_b = -cb.num_blobs;
  return std::tie(amb_a, fewer_a, ca.score, ca.key_blob, ca.pattern) <
         std::tie(amb_b, fewer_b, cb.score, cb.key_blob, cb.pattern);
}

// Stage 8's fixed output order.
bool OutputBefore(const Detection& a, const Detection& b) {
  return std::tie(a.pattern, a.team_colour, a.status, a.id, a.pose.x_mm, a.pose.y_mm) <
         std::tie(b.pattern, b.team_colour, b.status, b.id, b.pose.x_mm, b.pose.y_mm);
}

}  // namespace

// Stage 1, first part: each blob's x bucket (buckets one reach wide) for the neighbour search of
// stage 2 (NeighbourListOf sorts by it). Unusable blobs (non-finite, absurdly far) get -1.
void Detector::Impl::BucketBlobs(std::span<const Blob> blobs) {
  const int n = static_cast<int>(blobs.size());
  blob_bucket.resize(blobs.size());
  double min_x = 1e300, max_x = -1e300;
  for (int i = 0; i < n; ++i) {
    const Blob& b = blobs[i];
    const bool usable = Usable(b);
    blob_bucket[i] = usable ? 0 : -1;
    if (!usable) continue;
    min_x = std::min(min_x, b.position_mm.x());
    max_x = std::max(max_x, b.position_mm.x());
  }
  constexpr int kMaxBuckets = 4096;
  bucket_min_x = min_x <= max_x ? min_x : 0.0;
  const double range = min_x <= max_x ? max_x - min_x : 0.0;
  bucket_width_mm = std::max(max_reach_mm, range / (kMaxBuckets - 1));
  num_buckets = static_cast<int>(range / bucket_width_mm) + 1;
  // Also the Usable blobs of a key colour, in index order (compacted without a branch on them).
  key_blobs.resize(blobs.size());
  num_key_blobs = 0;
  for (int i = 0; i < n; ++i) {
    const int label = blobs[i].colour;
    const bool key_colour = (static_cast<unsigned>(label) < unsigned{kMaxLabels}) &
                            (((key_label_mask >> (label & (kMaxLabels - 1))) & 1) != 0);
    key_blobs[num_key_blobs] = i;
    num_key_blobs += static_cast<int>(key_colour & (blob_bucket[i] >= 0));
    if (blob_bucket[i] < 0) continue;
    blob_bucket[i] =
        std::min(num_buckets - 1,
                 static_cast<int>((blobs[i].position_mm.x() - bucket_min_x) / bucket_width_mm));
  }
}

// Stage 1: every (key blob, pattern) pair whose colour and area fit; stages 2-6 for each.
template <bool kTiming>
void Detector::Impl::FindKeyCandidates(std::span<const Blob> blobs) {
  for (int k = 0; k < num_key_blobs; ++k) {
    const int i = key_blobs[k];
    const int label = blobs[i].colour;
    for (int p : patterns_by_key_label[label]) {
      const PatternRuntime& rt = runtimes[p];
      if (blobs[i].area_mm2 < rt.key_area_min || blobs[i].area_mm2 > rt.key_area_max) {
        if (explain != nullptr) {
          KeyExplanation& e = explain->emplace_back();
          e.pattern = p;
          e.key_blob = i;
          e.outcome = KeyOutcome::kKeyArea;
          e.needed = rt.mk;
          e.best_e_mm2 = std::numeric_limits<double>::infinity();
          e.tolerance_mm2 = rt.e_max_full;
          e.nearest_blob.fill(-1);
        }
        continue;
      }
      ++stats.key_candidates;
      EvaluateKey<kTiming>(p, i, blobs);
    }
  }
}

// Stage 7: each blob goes to the best-ranked candidate that claims it; stage 8 (pose) for each
// candidate kept.
template <bool kTiming>
void Detector::Impl::ResolveConflicts(std::span<const Blob> blobs,
                                      std::vector<Detection>* detections) {
  const int nc = static_cast<int>(candidates.size());
  candidate_order.resize(nc);
  for (int i = 0; i < nc; ++i) candidate_order[i] = i;
  std::sort(candidate_order.begin(), candidate_order.end(),
            [&](int a, int b) { return RanksBefore(candidates[a], candidates[b]); });
  used.assign(blobs.size(), 0);
  for (int ci : candidate_order) {
    const Candidate& c = candidates[ci];
    const int m = runtimes[c.pattern].m;
    int taken_by = 0;  // 1 + the candidate holding one of c's blobs, or 0
    for (int i = 0; i < m && taken_by == 0; ++i) taken_by = c.blob[i] < 0 ? 0 : used[c.blob[i]];
    if (taken_by != 0) {
      ++stats.conflicts;
      if (explain != nullptr && c.explain >= 0) {
        KeyExplanation& e = (*explain)[static_cast<size_t>(c.explain)];
        e.outcome = KeyOutcome::kConflict;
        e.lost_to_key = candidates[taken_by - 1].key_blob;
        e.lost_to_pattern = candidates[taken_by - 1].pattern;
        for (int i = 0; i < m && e.lost_blob < 0; ++i) {
          if (c.blob[i] >= 0 && used[c.blob[i]] != 0) e.lost_blob = c.blob[i];
        }
      }
      continue;
    }
    for (int i = 0; i < m; ++i) {
      if (c.blob[i] >= 0) used[c.blob[i]] = ci + 1;
    }
    StageClock<kTiming> pose_clock;
    detections->emplace_back();
    EstimatePose(c, blobs, &detections->back());
    stage_ns[internal::kPose] += pose_clock.Lap();
    if (c.status == DetectionStatus::kAmbiguous) ++stats.ambiguous;
    if (c.status == DetectionStatus::kMissingPatch) ++stats.missing_fits;
  }
}

// Stage 8: the pose of one kept candidate with the chosen estimator, and its confidence.
void Detector::Impl::EstimatePose(const Candidate& c, std::span<const Blob> blobs,
                                  Detection* d) const {
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
    case estimate::Estimator::kRobust: {  // Huber at the detector's patch sigma
      estimate::RobustModel robust;
      robust.sigma_mm = std::sqrt(EffectiveSigma2Mm2(config.options));
      d->pose = estimate::Robust(model, observed.data(), robust, nullptr);
      break;
    }
  }
  const int dof = missing ? rt.dof_missing : rt.dof_full;
  const double sigma2 = EffectiveSigma2Mm2(config.options);
  d->confidence = ChiSquaredSurvival(dof, c.e / sigma2);
}

// The stages in order. Timed, the stages partition the call: stage 1 is the key loop less the
// per-key stages 2-6, stage 4 the full fits less the identification inside them, stage 7 the
// conflict pass less the poses in it, stage 8 the poses and the output order.
template <bool kTiming>
void Detector::Impl::DetectFrame(std::span<const Blob> blobs, std::vector<Detection>* detections) {
  StageClock<kTiming> clock;
  stage_ns.fill(0);
  stats = DetectStats{};
  ++frame_number;  // every NeighbourList is stale
  candidates.clear();
  detections->clear();
  BucketBlobs(blobs);
  FindKeyCandidates<kTiming>(blobs);
  const long keys_ns = clock.Lap();
  ResolveConflicts<kTiming>(blobs, detections);
  const long conflicts_ns = clock.Lap();
  SortDetections(detections);
  stats.detections = static_cast<long>(detections->size());
  if constexpr (kTiming) {
    using namespace internal;
    stage_ns[kFitRotations] -= stage_ns[kIdentify];
    stage_ns[kCandidates] = keys_ns - stage_ns[kNeighbours] - stage_ns[kRadialSort] -
                            stage_ns[kFitRotations] - stage_ns[kIdentify] - stage_ns[kMissingPatch];
    stage_ns[kConflicts] = conflicts_ns - stage_ns[kPose];
    stage_ns[kPose] += clock.Lap();
  }
}

// Stage 8's output order. std::sort of indices makes the same comparisons and the same moves as
// std::sort of the detections themselves, so the order (of equal keys too) is the one that
// sorting the detections gives, without moving them around.
void Detector::Impl::SortDetections(std::vector<Detection>* detections) {
  const int n = static_cast<int>(detections->size());
  detection_order.resize(detections->size());
  for (int i = 0; i < n; ++i) detection_order[i] = i;
  const std::vector<Detection>& d = *detections;
  std::sort(detection_order.begin(), detection_order.end(),
            [&d](int a, int b) { return OutputBefore(d[a], d[b]); });
  unsorted_detections.assign(detections->begin(), detections->end());
  for (int i = 0; i < n; ++i) (*detections)[i] = unsorted_detections[detection_order[i]];
}

// Explain: each kept candidate's record gets the index of its detection in the output order.
void Detector::Impl::LinkExplanations(const std::vector<Detection>& detections) {
  for (size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const int key = d.blob[static_cast<size_t>(runtimes[d.pattern].key_index)];
    for (KeyExplanation& e : *explain) {
      if (e.pattern == d.pattern && e.key_blob == key && e.outcome == KeyOutcome::kDetected) {
        e.detection = static_cast<int>(i);
      }
    }
  }
}

void Detector::Detect(std::span<const Blob> blobs, std::vector<Detection>* detections,
                      DetectStats* stats, TimeProfile* profile,
                      std::vector<KeyExplanation>* explain) {
  Impl& s = *impl_;
  s.explain = explain;
  if (explain != nullptr) explain->clear();
  if (profile != nullptr && profile->enabled()) {
    s.DetectFrame<true>(blobs, detections);
    for (int stage = 0; stage < internal::kNumStages; ++stage) {
      profile->Add(kDetectStageNames[stage], static_cast<double>(s.stage_ns[stage]) * 1e-9);
    }
  } else {
    s.DetectFrame<false>(blobs, detections);
  }
  if (explain != nullptr) s.LinkExplanations(*detections);
  s.explain = nullptr;
  if (stats != nullptr) *stats = s.stats;
}

}  // namespace patlab::detect

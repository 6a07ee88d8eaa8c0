// The explanation of a frame's detections (ExplanationText, `patlab detect --explain`): each key
// candidate's outcome, and the missing-patch looks of the fits that needed one.
#include <string>

#include "patlab/core/format.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/key_diagnosis.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::vision {

namespace {

// The MissingPatchLook of a detected key candidate, or nullptr.
const MissingPatchLook* LookOf(const detect::KeyExplanation& e, const FrameResult& r) {
  for (const MissingPatchLook& look : r.missing_patch_looks) {
    if (look.key_blob == e.key_blob && look.detection.pattern == e.pattern) return &look;
  }
  return nullptr;
}

// "its missing patch 1 shows 62% its colours, 3% other colours of 41 px"
std::string LookText(const MissingPatchLook& look) {
  const auto percent = [&look](int n) {
    return FormatFixed(look.pixels > 0 ? 100.0 * n / look.pixels : 0.0, 0) + "%";
  };
  return "missing patch " + std::to_string(look.detection.missing_patch) + " shows " +
         percent(look.own) + " its colours, " + percent(look.other) + " other colours of " +
         std::to_string(look.pixels) + " px";
}

// A detection's line (with what its missing patch shows), or the detector's diagnosis
// (detect::DiagnosisText: measures against bounds, nearest rotation, the setting change).
std::string OutcomeText(size_t index, const FrameResult& r, const detect::DetectorConfig& config) {
  const detect::KeyExplanation& e = r.explanations[index];
  const std::string tolerance = FormatSignificant(e.tolerance_mm2, 4) + " mm^2";
  if (e.outcome == detect::KeyOutcome::kDetected) {
    const MissingPatchLook* look = LookOf(e, r);
    if (look != nullptr && look->rejected) {
      return "missing_patch_colour: fitted without patch " +
             std::to_string(look->detection.missing_patch) + " (E " +
             FormatSignificant(look->detection.residual_mm2, 4) + " mm^2 <= tolerance " +
             tolerance + ") but " + LookText(*look) +
             ": another colour is there; change: no tolerance (the thresholds of that colour)";
    }
    if (e.detection < 0) return "detected";
    const detect::Detection& d = r.detections[static_cast<size_t>(e.detection)];
    std::string text = "detected, id " + std::to_string(d.id) + " (" +
                       std::string(detect::DetectionStatusName(d.status)) + "), E " +
                       FormatSignificant(d.residual_mm2, 4) + " mm^2 <= tolerance " + tolerance;
    if (look != nullptr) text.append("; ").append(LookText(*look));
    return text;
  }
  if (index < r.diagnoses.size()) {
    return detect::DiagnosisText(r.diagnoses[index], config, r.detector_blobs);
  }
  return std::string(NameOf(e.outcome, detect::kKeyOutcomeNames));
}

}  // namespace

std::string ExplanationText(const FrameResult& r, const FrameDetector& frames) {
  if (!frames.has_detector()) return "";
  const detect::DetectorConfig& config = frames.detector().config();
  std::string out;
  for (size_t i = 0; i < r.explanations.size(); ++i) {
    const detect::KeyExplanation& e = r.explanations[i];
    const detect::Blob& b = r.detector_blobs[static_cast<size_t>(e.key_blob)];
    const Region& region = r.blob_regions[static_cast<size_t>(
        r.detector_blob_source[static_cast<size_t>(e.key_blob)])];
    out.append(r.frame)
        .append(": key ")
        .append(std::to_string(e.key_blob))
        .append(" ")
        .append(config.palette[static_cast<size_t>(b.colour)])
        .append(" at (")
        .append(FormatFixed(region.centroid_px.x(), 1))
        .append(", ")
        .append(FormatFixed(region.centroid_px.y(), 1))
        .append(") px, (")
        .append(FormatFixed(b.position_mm.x(), 1))
        .append(", ")
        .append(FormatFixed(b.position_mm.y(), 1))
        .append(") mm, ")
        .append(config.patterns[static_cast<size_t>(e.pattern)].pattern.name)
        .append(": ")
        .append(OutcomeText(i, r, config))
        .append("\n");
  }
  return out;
}

}  // namespace patlab::vision

// The explanation of a frame's detections (ExplanationText, `patlab detect --explain`): each key
// candidate's outcome, and the missing-patch looks of the fits that needed one.
#include <string>

#include "patlab/core/format.h"
#include "patlab/detect/detector.h"
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

std::string OutcomeText(const detect::KeyExplanation& e, const FrameResult& r,
                        const detect::DetectorConfig& config) {
  const std::string tolerance = FormatSignificant(e.tolerance_mm2, 4) + " mm^2";
  switch (e.outcome) {
    case detect::KeyOutcome::kDetected: {
      const MissingPatchLook* look = LookOf(e, r);
      if (look != nullptr && look->rejected) {
        return "missing_patch_colour: fitted without patch " +
               std::to_string(look->detection.missing_patch) + " (E " +
               FormatSignificant(look->detection.residual_mm2, 4) + " mm^2 <= tolerance " +
               tolerance + ") but " + LookText(*look) + ": another colour is there";
      }
      if (e.detection < 0) return "detected";
      const detect::Detection& d = r.detections[static_cast<size_t>(e.detection)];
      std::string text = "detected, id " + std::to_string(d.id) + " (" +
                         std::string(detect::DetectionStatusName(d.status)) + "), E " +
                         FormatSignificant(d.residual_mm2, 4) + " mm^2 <= tolerance " + tolerance;
      if (look != nullptr) text.append("; ").append(LookText(*look));
      return text;
    }
    case detect::KeyOutcome::kKeyArea:
      return "key_area: " +
             FormatSignificant(r.detector_blobs[static_cast<size_t>(e.key_blob)].area_mm2, 4) +
             " mm^2 is outside the key patch's area range (area_ratio_min, area_ratio_max)";
    case detect::KeyOutcome::kFewNeighbours:
      return "few_neighbours: " + std::to_string(e.neighbours) + " within reach, " +
             std::to_string(e.needed) +
             " needed (check reach_margin_mm, the neighbours' areas and colours)";
    case detect::KeyOutcome::kGeometry:
      return "geometry: best rotation E " + FormatSignificant(e.best_e_mm2, 4) +
             " mm^2 > tolerance " + tolerance + " (" + std::to_string(e.rotations) +
             " rotations tried; check patch_sigma_mm and the calibration)";
    case detect::KeyOutcome::kColours:
      return "colours: " + std::to_string(e.geometry_passed) +
             " rotation(s) passed geometry (best E " + FormatSignificant(e.best_e_mm2, 4) +
             " mm^2) but their colours are no ID of the codebook";
    case detect::KeyOutcome::kConflict:
      return "conflict: lost a blob to key " + std::to_string(e.lost_to_key) + " (" +
             config.patterns[static_cast<size_t>(e.lost_to_pattern)].pattern.name + ")";
  }
  return "";
}

}  // namespace

std::string ExplanationText(const FrameResult& r, const FrameDetector& frames) {
  if (!frames.has_detector()) return "";
  const detect::DetectorConfig& config = frames.detector().config();
  std::string out;
  for (const detect::KeyExplanation& e : r.explanations) {
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
        .append(OutcomeText(e, r, config))
        .append("\n");
  }
  return out;
}

}  // namespace patlab::vision

// The one text form of a KeyDiagnosis (key_diagnosis.h): measures against bounds, the blobs not
// counted, the nearest rotation, the colours, and the setting change.
#include <string>

#include "patlab/core/format.h"
#include "patlab/detect/key_diagnosis.h"

namespace patlab::detect {

namespace {

std::string Number(double value) { return FormatSignificant(value, 3); }

std::string ColourOf(const DetectorConfig& config, const Blob& b) {
  return b.colour >= 0 && b.colour < static_cast<int>(config.palette.size())
             ? config.palette[static_cast<size_t>(b.colour)]
             : "?";
}

// "blob 7 pink: distance 92.1 mm > reach 85 mm"
std::string WouldBeText(const WouldBeNeighbour& w, const std::string& colour) {
  std::string text = "blob " + std::to_string(w.blob) + " " + colour + ":";
  if (!w.colour_ok) text += " not a colour of the pattern's patches,";
  if (w.distance_mm < w.reach_min_mm) {
    text += " distance " + Number(w.distance_mm) + " mm < reach " + Number(w.reach_min_mm) + " mm,";
  } else if (w.distance_mm > w.reach_max_mm) {
    text += " distance " + Number(w.distance_mm) + " mm > reach " + Number(w.reach_max_mm) + " mm,";
  } else {
    text += " distance " + Number(w.distance_mm) + " mm within reach,";
  }
  if (w.area_ratio < w.area_ratio_min) {
    text += " area ratio " + Number(w.area_ratio) + " < " + Number(w.area_ratio_min);
  } else if (w.area_ratio > w.area_ratio_max) {
    text += " area ratio " + Number(w.area_ratio) + " > " + Number(w.area_ratio_max);
  } else {
    text += " area ratio " + Number(w.area_ratio) + " in range";
  }
  return text;
}

// "nearest rotation 1: patch 1 blob 5, patch 2 blob 8"
std::string RotationText(const KeyExplanation& e, const DetectorConfig& config) {
  const int m = config.patterns[static_cast<size_t>(e.pattern)].pattern.size();
  std::string text = "nearest rotation " + std::to_string(e.nearest_rotation) + ":";
  for (int i = 0; i < m; ++i) {
    const int b = e.nearest_blob[static_cast<size_t>(i)];
    text += (i == 0 ? " patch " : ", patch ") + std::to_string(i) + " blob " +
            (b >= 0 ? std::to_string(b) : std::string("-"));
  }
  return text;
}

std::string ColoursText(const KeyDiagnosis& d) {
  std::string text = d.colour_problem;
  if (!d.patch_colours.empty()) {
    text += " (patch colours";
    for (const std::string& c : d.patch_colours) text.append(" ").append(c.empty() ? "-" : c);
    text += ")";
  }
  if (d.nearest_id >= 0) {
    text += "; nearest ID " + std::to_string(d.nearest_id) + " differs at patch";
    for (size_t i = 0; i < d.nearest_id_differs.size(); ++i) {
      text.append(i == 0 ? " " : ", ").append(std::to_string(d.nearest_id_differs[i]));
    }
  }
  return text;
}

}  // namespace

std::string SettingChangeText(const SettingChange& change) {
  return change.key + " " + FormatNumber(change.from) + " -> " + FormatNumber(change.to);
}

std::string StageMeasureText(const StageMeasure& m) {
  const std::string unit = m.unit.empty() ? "" : " " + m.unit;
  const int digits = m.unit == "mm^2" ? 4 : 3;
  return m.quantity + " " + FormatSignificant(m.value, digits) + unit + " " + m.relation + " " +
         FormatSignificant(m.bound, digits) + unit + (m.note.empty() ? "" : " (" + m.note + ")");
}

std::string DiagnosisText(const KeyDiagnosis& d, const DetectorConfig& config,
                          std::span<const Blob> blobs) {
  const KeyExplanation& e = d.explanation;
  std::string text(NameOf(e.outcome, kKeyOutcomeNames));
  text += ":";
  for (size_t i = 0; i < d.measures.size(); ++i) {
    text.append(i == 0 ? " " : "; ").append(StageMeasureText(d.measures[i]));
  }
  if (e.outcome == KeyOutcome::kFewNeighbours && !d.would_be.empty()) {
    text += "; not counted:";
    for (size_t i = 0; i < d.would_be.size(); ++i) {
      const WouldBeNeighbour& w = d.would_be[i];
      text.append(i == 0 ? " " : "; ")
          .append(WouldBeText(w, ColourOf(config, blobs[static_cast<size_t>(w.blob)])));
    }
  }
  if (e.outcome == KeyOutcome::kColours) text += "; " + ColoursText(d);
  if (e.outcome == KeyOutcome::kConflict) {
    text += "; lost blob " + std::to_string(e.lost_blob) + " to key " +
            std::to_string(e.lost_to_key) + " (" +
            config.patterns[static_cast<size_t>(e.lost_to_pattern)].pattern.name + ")";
  }
  if (e.nearest_rotation >= 0) text += "; " + RotationText(e, config);
  if (d.nearest_pattern && config.patterns.size() > 1) text += "; nearest pattern of this key";
  if (d.change) {
    text += "; change " + SettingChangeText(*d.change) + " (then id " +
            std::to_string(d.accepted.id) + ", " +
            std::string(NameOf(d.accepted.status, kDetectionStatusNames)) + ")";
  } else if (!d.no_change.empty()) {
    text += "; change: " + d.no_change;
  }
  return text;
}

}  // namespace patlab::detect

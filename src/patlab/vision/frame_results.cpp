#include "patlab/vision/frame_results.h"

#include <nlohmann/json.hpp>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/csv.h"

namespace patlab::vision {

struct FrameResultsWriter::JsonFrames {
  nlohmann::json frames = nlohmann::json::array();
};

FrameResultsWriter::FrameResultsWriter(const FrameDetector& frames, bool blobs)
    : frames_(frames),
      blobs_(blobs || !frames.has_detector()),
      json_(std::make_unique<JsonFrames>()) {
  csv_ = blobs_ ? "frame,colour,x_mm,y_mm,area_mm2,x_px,y_px,area_px\n"
                : "frame,pattern,team,id,status,x_mm,y_mm,theta_rad,residual_mm2,confidence\n";
}

FrameResultsWriter::~FrameResultsWriter() = default;

void FrameResultsWriter::Add(const FrameResult& frame) {
  if (blobs_) {
    AddBlobs(frame);
  } else {
    AddDetections(frame);
  }
}

void FrameResultsWriter::AddBlobs(const FrameResult& frame) {
  const Thresholds& thresholds = frames_.pipeline().thresholds();
  nlohmann::json list = nlohmann::json::array();
  for (size_t i = 0; i < frame.blobs.size(); ++i) {
    const detect::Blob& b = frame.blobs[i];
    const Region& r = frame.blob_regions[i];
    const std::string& colour = thresholds.classes[static_cast<size_t>(b.colour)].name;
    io::CsvWriter(&csv_)
        .Cells({frame.frame, colour, FormatFixed(b.position_mm.x(), 2),
                FormatFixed(b.position_mm.y(), 2), FormatFixed(b.area_mm2, 1),
                FormatFixed(r.centroid_px.x(), 3), FormatFixed(r.centroid_px.y(), 3)})
        .Cell(static_cast<int64_t>(r.area_px))
        .EndRow();
    list.push_back({{"colour", colour},
                    {"x_mm", b.position_mm.x()},
                    {"y_mm", b.position_mm.y()},
                    {"area_mm2", b.area_mm2},
                    {"x_px", r.centroid_px.x()},
                    {"y_px", r.centroid_px.y()},
                    {"area_px", r.area_px}});
  }
  json_->frames.push_back({{"frame", frame.frame}, {"blobs", list}});
}

namespace {

// --explain's diagnoses (detect::KeyDiagnosis) as JSON: the same facts as the text, as data.
nlohmann::json DiagnosesJson(const FrameResult& frame, const detect::DetectorConfig& config) {
  nlohmann::json out = nlohmann::json::array();
  for (const detect::KeyDiagnosis& d : frame.diagnoses) {
    const detect::KeyExplanation& e = d.explanation;
    nlohmann::json measures = nlohmann::json::array();
    for (const detect::StageMeasure& m : d.measures) {
      measures.push_back({{"quantity", m.quantity},
                          {"value", m.value},
                          {"relation", m.relation},
                          {"bound", m.bound},
                          {"unit", m.unit}});
    }
    nlohmann::json blobs = nlohmann::json::array();
    const int m = config.patterns[static_cast<size_t>(e.pattern)].pattern.size();
    for (int i = 0; i < m && e.nearest_rotation >= 0; ++i) {
      blobs.push_back(e.nearest_blob[static_cast<size_t>(i)]);
    }
    nlohmann::json change = nullptr;
    if (d.change) {
      change = {{"key", d.change->key},
                {"from", d.change->from},
                {"to", d.change->to},
                {"id", d.accepted.id},
                {"status", std::string(NameOf(d.accepted.status, detect::kDetectionStatusNames))}};
    }
    out.push_back({{"key_blob", e.key_blob},
                   {"pattern", config.patterns[static_cast<size_t>(e.pattern)].pattern.name},
                   {"outcome", std::string(NameOf(e.outcome, detect::kKeyOutcomeNames))},
                   {"measures", measures},
                   {"nearest_rotation", e.nearest_rotation},
                   {"nearest_rotation_blobs", blobs},
                   {"nearest_pattern", d.nearest_pattern},
                   {"change", change},
                   {"no_change", d.no_change},
                   {"text", detect::DiagnosisText(d, config, frame.detector_blobs)}});
  }
  return out;
}

}  // namespace

void FrameResultsWriter::AddDetections(const FrameResult& frame) {
  const detect::DetectorConfig& config = frames_.detector().config();
  nlohmann::json list = nlohmann::json::array();
  for (const detect::Detection& d : frame.detections) {
    const std::string& pattern = config.patterns[static_cast<size_t>(d.pattern)].pattern.name;
    const std::string team =
        d.team_colour >= 0 ? config.palette[static_cast<size_t>(d.team_colour)] : "";
    const std::string status(NameOf(d.status, detect::kDetectionStatusNames));
    io::CsvWriter(&csv_)
        .Cells({frame.frame, pattern, team})
        .Cell(static_cast<int64_t>(d.id))
        .Cells({status, FormatFixed(d.pose.x_mm, 2), FormatFixed(d.pose.y_mm, 2),
                FormatFixed(d.pose.theta_rad, 4), FormatFixed(d.residual_mm2, 2),
                FormatFixed(d.confidence, 4)})
        .EndRow();
    list.push_back({{"pattern", pattern},
                    {"team", team},
                    {"id", d.id},
                    {"status", status},
                    {"x_mm", d.pose.x_mm},
                    {"y_mm", d.pose.y_mm},
                    {"theta_rad", d.pose.theta_rad},
                    {"residual_mm2", d.residual_mm2},
                    {"confidence", d.confidence}});
  }
  nlohmann::json entry = {{"frame", frame.frame}, {"detections", list}};
  if (!frame.diagnoses.empty()) entry["explanations"] = DiagnosesJson(frame, config);
  json_->frames.push_back(std::move(entry));
}

std::string FrameResultsWriter::Csv() const { return csv_; }

std::string FrameResultsWriter::Json() const { return json_->frames.dump(2) + "\n"; }

TrackWriter::TrackWriter(const FrameDetector& frames) : frames_(frames) {
  PATLAB_CHECK(frames.has_detector());
}

void TrackWriter::Add(int64_t frame_index, const FrameResult& frame) {
  const detect::DetectorConfig& config = frames_.detector().config();
  std::map<std::string, std::pair<int, Pose2>> seen;  // subject -> (count, pose)
  for (const detect::Detection& d : frame.detections) {
    if (d.status != detect::DetectionStatus::kOk || d.id < 0 || d.team_colour < 0) continue;
    std::string subject = config.palette[static_cast<size_t>(d.team_colour)];
    subject.append("-").append(std::to_string(d.id));
    auto& [count, pose] = seen[subject];
    ++count;
    pose = d.pose;
  }
  for (const auto& [subject, entry] : seen) {
    if (entry.first > 1) {
      ++duplicates_;
      continue;
    }
    std::vector<Sample>& track = tracks_[subject];
    PATLAB_CHECK(track.empty() || track.back().frame < frame_index);
    track.push_back({frame_index, entry.second});
  }
}

std::string TrackWriter::Csv() const {
  std::string csv = "frame,subject,x_mm,y_mm,theta_rad\n";
  for (const auto& [subject, track] : tracks_) {
    for (const Sample& s : track) {
      io::CsvWriter(&csv)
          .Cell(s.frame)
          .Cells({subject, FormatFixed(s.pose.x_mm, 3), FormatFixed(s.pose.y_mm, 3),
                  FormatFixed(s.pose.theta_rad, 5)})
          .EndRow();
    }
  }
  return csv;
}

}  // namespace patlab::vision

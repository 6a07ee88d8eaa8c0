// patlab detect's result files: the detections (or the calibrated blobs) of many frames as CSV or
// JSON text. The CSV has one row per detection (or blob) with a fixed number of decimals per
// column (format.h FormatFixed); the JSON is an array of frames, each with its "detections" (or
// "blobs"), numbers in full precision. Columns and fields:
//   detections: frame, pattern, team, id, status, x_mm, y_mm, theta_rad, residual_mm2, confidence
//   blobs:      frame, colour, x_mm, y_mm, area_mm2, x_px, y_px, area_px
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "patlab/vision/frame_detector.h"

namespace patlab::vision {

class FrameResultsWriter {
 public:
  // `blobs`: write the calibrated blobs instead of the detections (always so when `frames` has no
  // detector). `frames` must outlive the writer.
  FrameResultsWriter(const FrameDetector& frames, bool blobs);
  ~FrameResultsWriter();

  bool writes_blobs() const { return blobs_; }
  // Appends one frame's rows.
  void Add(const FrameResult& frame);
  std::string Csv() const;
  std::string Json() const;

 private:
  struct JsonFrames;
  void AddBlobs(const FrameResult& frame);
  void AddDetections(const FrameResult& frame);

  const FrameDetector& frames_;
  bool blobs_;
  std::string csv_;
  std::unique_ptr<JsonFrames> json_;
};

// patlab detect --track: the detections of a frame sequence as a track CSV that `patlab analyze`
// reads directly (analysis/analyze.h, docs/file-formats.md "Track CSV"): header
//   frame,subject,x_mm,y_mm,theta_rad
// frame = the frame's index in the sequence (0, 1, ...: the order the frames were given), subject
// = "<team>-<id>" (e.g. "blue-3"). Only detections with status "ok" and a known ID are written; a
// subject detected more than once in one frame is left out of that frame (its identity is in
// doubt), so a frame without it is a gap for the analysis. Rows are sorted by subject, then frame.
class TrackWriter {
 public:
  // `frames` must outlive the writer and have a detector.
  explicit TrackWriter(const FrameDetector& frames);
  // Appends the robots of frame number `frame_index` (increasing from call to call).
  void Add(int64_t frame_index, const FrameResult& frame);
  std::string Csv() const;
  // Frames in which a subject was seen more than once (and so left out), summed over subjects.
  int duplicates() const { return duplicates_; }

 private:
  struct Sample {
    int64_t frame;
    Pose2 pose;
  };
  const FrameDetector& frames_;
  std::map<std::string, std::vector<Sample>> tracks_;
  int duplicates_ = 0;
};

}  // namespace patlab::vision

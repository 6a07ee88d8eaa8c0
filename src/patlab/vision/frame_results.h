// patlab detect's result files: the detections (or the calibrated blobs) of many frames as CSV or
// JSON text. The CSV has one row per detection (or blob) with a fixed number of decimals per
// column (format.h FormatFixed); the JSON is an array of frames, each with its "detections" (or
// "blobs"), numbers in full precision. Columns and fields:
//   detections: frame, pattern, team, id, status, x_mm, y_mm, theta_rad, residual_mm2, confidence
//   blobs:      frame, colour, x_mm, y_mm, area_mm2, x_px, y_px, area_px
#pragma once

#include <memory>
#include <string>

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

}  // namespace patlab::vision

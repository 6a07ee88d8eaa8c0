// The real-frame low-level vision pipeline (paper section III: CMVision feeding the detector),
// as numbered stages with per-stage timing and counters (docs/architecture.md rule 8):
//   1. read      - frame_io.h (timed by the caller, which owns the files);
//   2. classify  - colour lookup table -> class image;
//   3. encode    - run-length encoding + union-find of runs;
//   4. regions   - region statistics, area / fill filters, per-class sort;
//   5. camera    - region centroid and area -> mm on the plane at the class's height;
//   6. detect    - detect::Detector on the blobs (in cli/, when patterns are given).
#pragma once

#include <string>
#include <vector>

#include "patlab/detect/blob.h"
#include "patlab/vision/camera.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/image.h"
#include "patlab/vision/segment.h"

namespace patlab::vision {

struct VisionStats {
  double classify_ms = 0.0;  // stage 2
  double encode_ms = 0.0;    // stage 3
  double regions_ms = 0.0;   // stage 4
  double camera_ms = 0.0;    // stage 5
  long runs = 0;             // stage 3: runs of any class
  long raw_regions = 0;      // stage 4: connected regions before filters
  long regions = 0;          // stage 4: regions kept
  long blobs = 0;            // stage 5: regions mapped to the plane
  long off_plane = 0;        // stage 5: regions whose centroid does not map (dropped)

  VisionStats& operator+=(const VisionStats& o);
};

class VisionPipeline {
 public:
  // Throws InputError when the calibration cannot map some class's plane height (a homography
  // calibration without a matrix for it).
  VisionPipeline(Thresholds thresholds, Calibration calibration, const SegmenterOptions& options);

  // InputError "frame: image is WxH; expected WxH as in calibration" when the calibration
  // names an image size and the frame differs.
  void CheckFrameSize(const Image& image, const std::string& frame_name) const;

  // Stages 2-5. `blobs` is cleared and filled in region order (class, then area); blob i
  // came from segmenter().regions()[blob_region()[i]]. Blob colours are class indices.
  void Process(const Image& image, std::vector<detect::Blob>* blobs, VisionStats* stats = nullptr);

  const Segmenter& segmenter() const { return segmenter_; }
  const Thresholds& thresholds() const { return thresholds_; }
  const Calibration& calibration() const { return calibration_; }
  const std::vector<int>& blob_region() const { return blob_region_; }
  double class_height_mm(int colour) const { return heights_mm_[colour]; }

 private:
  Thresholds thresholds_;
  Calibration calibration_;
  Segmenter segmenter_;
  std::vector<double> heights_mm_;  // per class
  std::vector<int> blob_region_;
};

}  // namespace patlab::vision

// The real-frame low-level vision pipeline (paper section III: CMVision feeding the detector),
// as numbered stages with per-stage timing and counters (docs/architecture.md rule 8). The stage
// names, numbered once here and used as they are in every TimeProfile (kFrameStageNames):
//   1 read          - frame_io.h: the frame file decoded (FrameDetector);
//   2 colour lookup - colour lookup table -> class image (Segmenter::Classify);
//   3 runs          - run-length encoding + union-find of runs (Segmenter::EncodeRuns);
//   4 regions       - region statistics, area / fill filters, per-class sort
//                     (Segmenter::ExtractRegions);
//   5 blobs to mm   - region centroid and area -> mm on the plane at the class's height (camera);
//   6 detect        - detect::Detector on the blobs of its palette (FrameDetector), whose own
//                     stages are numbered in detect/detector.h.
// VisionPipeline runs stages 2-5; FrameDetector (frame_detector.h) the whole frame.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/timeprofile.h"

#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/detect/blob.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/segment.h"

namespace patlab::vision {

inline constexpr std::array<std::string_view, 6> kFrameStageNames = {
    "1 read", "2 colour lookup", "3 runs", "4 regions", "5 blobs to mm", "6 detect"};

// Per-frame counters of stages 3-5 (summed over frames by operator+=).
struct VisionStats {
  long runs = 0;         // stage 3: runs of any class
  long raw_regions = 0;  // stage 4: connected regions before filters
  long regions = 0;      // stage 4: regions kept
  long blobs = 0;        // stage 5: regions mapped to the plane
  long off_plane = 0;    // stage 5: regions whose centroid does not map (dropped)

  VisionStats& operator+=(const VisionStats& o);
};

// InputError "frame: image is WxH; expected WxH as in <calibration's source>" when the
// calibration names an image size and the frame's differs.
void CheckFrameSize(const camera::Calibration& calibration, int width_px, int height_px,
                    const std::string& frame_name);

class VisionPipeline {
 public:
  // Throws InputError when the calibration cannot map some class's plane height (a homography
  // calibration without a matrix for it).
  VisionPipeline(Thresholds thresholds, camera::Calibration calibration,
                 const SegmenterOptions& options);

  // InputError "frame: image is WxH; expected WxH as in calibration" when the calibration
  // names an image size and the frame differs.
  void CheckFrameSize(const camera::ImageView& image, const std::string& frame_name) const;
  // The same from a size alone (a frame's header, before its pixels are decoded).
  void CheckFrameSize(int width_px, int height_px, const std::string& frame_name) const;

  // Stages 2-5. `blobs` is cleared and filled in region order (class, then area); blob i
  // came from segmenter().regions()[blob_region()[i]]. Blob colours are class indices. `stats`
  // (optional) is overwritten; an enabled `profile` gets the time of stages 2-5 added under
  // their names (no clock is read otherwise).
  void Process(const camera::ImageView& image, std::vector<detect::Blob>* blobs,
               VisionStats* stats = nullptr, TimeProfile* profile = nullptr);

  const Segmenter& segmenter() const { return segmenter_; }
  const Thresholds& thresholds() const { return thresholds_; }
  const camera::Calibration& calibration() const { return calibration_; }
  const std::vector<int>& blob_region() const { return blob_region_; }
  double class_height_mm(int colour) const { return heights_mm_[colour]; }

 private:
  Thresholds thresholds_;
  camera::Calibration calibration_;
  Segmenter segmenter_;
  std::vector<double> heights_mm_;  // per class
  std::vector<int> blob_region_;
};

}  // namespace patlab::vision

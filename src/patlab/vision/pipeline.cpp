#include "patlab/vision/pipeline.h"

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::vision {

VisionStats& VisionStats::operator+=(const VisionStats& o) {
  runs += o.runs;
  raw_regions += o.raw_regions;
  regions += o.regions;
  blobs += o.blobs;
  off_plane += o.off_plane;
  return *this;
}

VisionPipeline::VisionPipeline(Thresholds thresholds, camera::Calibration calibration,
                               const SegmenterOptions& options)
    : thresholds_(std::move(thresholds)),
      calibration_(std::move(calibration)),
      segmenter_(thresholds_, options) {
  for (const auto& [name, height] : calibration_.class_height_mm) {
    if (thresholds_.Find(name) < 0) {
      std::string names;
      for (const ColorClass& c : thresholds_.classes) names += (names.empty() ? "" : ", ") + c.name;
      throw InputError(calibration_.source + ": [heights] names class '" + name + "', which " +
                       thresholds_.source + " does not define; expected one of: " + names);
    }
  }
  for (const ColorClass& c : thresholds_.classes) {
    const double h = calibration_.HeightOf(c.name);
    if (!calibration_.camera.SupportsHeight(h)) {
      throw InputError(calibration_.source + ": no homography for height " + FormatNumber(h) +
                       " mm (class '" + c.name +
                       "'); expected a [[homography]] with that height_mm");
    }
    heights_mm_.push_back(h);
  }
}

void VisionPipeline::CheckFrameSize(const camera::ImageView& image,
                                    const std::string& frame_name) const {
  CheckFrameSize(image.width_px, image.height_px, frame_name);
}

void VisionPipeline::CheckFrameSize(int width_px, int height_px,
                                    const std::string& frame_name) const {
  vision::CheckFrameSize(calibration_, width_px, height_px, frame_name);
}

void CheckFrameSize(const camera::Calibration& calibration, int width_px, int height_px,
                    const std::string& frame_name) {
  if (calibration.image_width_px == 0) return;
  if (width_px != calibration.image_width_px || height_px != calibration.image_height_px) {
    throw InputError(frame_name + ": image is " + std::to_string(width_px) + "x" +
                     std::to_string(height_px) + "; expected " +
                     std::to_string(calibration.image_width_px) + "x" +
                     std::to_string(calibration.image_height_px) + " as in " + calibration.source);
  }
}

void VisionPipeline::Process(const camera::ImageView& image, std::vector<detect::Blob>* blobs,
                             VisionStats* stats, TimeProfile* profile) {
  TimeProfile untimed;
  TimeProfile& time = profile != nullptr ? *profile : untimed;
  VisionStats s;
  time.Start();
  segmenter_.Classify(image);
  time.Stamp(kFrameStageNames[1]);

  segmenter_.EncodeRuns();
  s.runs = static_cast<long>(segmenter_.runs().size());
  time.Stamp(kFrameStageNames[2]);

  segmenter_.ExtractRegions();
  s.raw_regions = segmenter_.num_raw_regions();
  s.regions = static_cast<long>(segmenter_.regions().size());
  time.Stamp(kFrameStageNames[3]);

  blobs->clear();
  blob_region_.clear();
  const std::vector<Region>& regions = segmenter_.regions();
  for (size_t i = 0; i < regions.size(); ++i) {
    const Region& r = regions[i];
    const double height = heights_mm_[r.colour];
    const auto world = calibration_.camera.PixelToWorld(r.centroid_px, height);
    const double scale = calibration_.camera.AreaScale(r.centroid_px, height);
    if (!world || scale <= 0.0) {
      ++s.off_plane;
      continue;
    }
    blobs->push_back(detect::Blob{*world, r.colour, r.area_px * scale});
    blob_region_.push_back(static_cast<int>(i));
  }
  s.blobs = static_cast<long>(blobs->size());
  time.Stamp(kFrameStageNames[4]);
  if (stats != nullptr) *stats = s;
}

}  // namespace patlab::vision

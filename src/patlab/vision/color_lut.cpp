#include "patlab/vision/color_lut.h"

#include "patlab/core/error.h"

namespace patlab::vision {

int Thresholds::Find(std::string_view name) const {
  for (size_t i = 0; i < classes.size(); ++i) {
    if (classes[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

ColorLut::ColorLut(const Thresholds& thresholds)
    : space_(thresholds.space), num_classes_(static_cast<int>(thresholds.classes.size())) {
  PATLAB_CHECK(num_classes_ <= kMaxColorClasses);
  for (int k = 0; k < num_classes_; ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      const ChannelRange& range = thresholds.classes[k].range[ch];
      for (int v = range.lo; v <= range.hi; ++v) tables_[ch][v] |= uint32_t{1} << k;
    }
  }
}

}  // namespace patlab::vision

// Labels files: pixels of a frame labelled with colour classes, the input of the thresholds fit
// (vision/thresholds_fit.h, patlab thresholds; format in docs/file-formats.md, "Labels files").
#pragma once

#include <string>
#include <string_view>

#include "patlab/vision/thresholds_fit.h"

namespace patlab::formats {

// `base_dir` resolves the relative image and mask paths. InputError at the offending line for
// bad syntax, unknown keys, duplicate or empty names, malformed points or rectangles, a class
// with no samples at all.
vision::Labels ParseLabels(std::string_view text, const std::string& name,
                           const std::string& base_dir);
vision::Labels LoadLabels(const std::string& path);

}  // namespace patlab::formats

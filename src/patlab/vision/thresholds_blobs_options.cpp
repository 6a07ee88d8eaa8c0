// The colour fit's options by name (vision/thresholds_blobs.h), for `patlab setup
// --colour-option NAME=VALUE` and patlab.setup(colour_options=...).
#include <cmath>
#include <variant>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/vision/thresholds_blobs.h"

namespace patlab::vision {

namespace {

using Field = std::variant<double BlobThresholdsOptions::*, int BlobThresholdsOptions::*>;

// Every option but the blob area range and spread, which setup sets from the calibration and
// the patterns (formats::SetupBlobAreas).
const std::vector<std::pair<std::string, Field>>& NamedFields() {
  static const std::vector<std::pair<std::string, Field>> fields = {
      {"light_cell_px", &BlobThresholdsOptions::light_cell_px},
      {"max_light_gain", &BlobThresholdsOptions::max_light_gain},
      {"standout_delta_e", &BlobThresholdsOptions::standout_delta_e},
      {"segment_k", &BlobThresholdsOptions::segment_k},
      {"cluster_distance", &BlobThresholdsOptions::cluster_distance},
      {"lightness_weight", &BlobThresholdsOptions::lightness_weight},
      {"hue_spread_deg", &BlobThresholdsOptions::hue_spread_deg},
      {"lightness_spread", &BlobThresholdsOptions::lightness_spread},
      {"chroma_spread", &BlobThresholdsOptions::chroma_spread},
      {"achromatic_chroma", &BlobThresholdsOptions::achromatic_chroma},
      {"max_name_cost", &BlobThresholdsOptions::max_name_cost},
      {"lower_percentile", &BlobThresholdsOptions::lower_percentile},
      {"upper_percentile", &BlobThresholdsOptions::upper_percentile},
      {"lighting_min_gain", &BlobThresholdsOptions::lighting_min_gain},
      {"lighting_max_gain", &BlobThresholdsOptions::lighting_max_gain},
      {"margin_levels", &BlobThresholdsOptions::margin_levels},
      {"negative_weight", &BlobThresholdsOptions::negative_weight}};
  return fields;
}

}  // namespace

std::vector<std::string> BlobThresholdsOptionNames() {
  std::vector<std::string> names;
  for (const auto& [name, field] : NamedFields()) names.push_back(name);
  return names;
}

void SetBlobThresholdsOption(const std::string& name, double value,
                             BlobThresholdsOptions* options) {
  for (const auto& [known, field] : NamedFields()) {
    if (known != name) continue;
    if (const auto* d = std::get_if<double BlobThresholdsOptions::*>(&field)) {
      options->** d = value;
    } else {
      if (!std::isfinite(value) || value != std::round(value) || std::abs(value) > 1e9)
        throw InputError(name + " is " + FormatNumber(value) + "; expected an integer");
      options->*std::get<int BlobThresholdsOptions::*>(field) = static_cast<int>(value);
    }
    return;
  }
  std::string expected;
  for (const std::string& n : BlobThresholdsOptionNames())
    expected += (expected.empty() ? "" : ", ") + n;
  throw InputError("unknown colour option '" + name + "'; expected one of " + expected);
}

}  // namespace patlab::vision

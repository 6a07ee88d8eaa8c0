// Shared helpers of the detect tests.
#pragma once

#include <string>
#include <vector>

#include "patlab/core/pattern.h"
#include "patlab/core/rng.h"
#include "patlab/detect/blob.h"
#include "patlab/detect/detector.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/pattern_file.h"

namespace patlab::detect::testing {

inline const std::vector<std::string> kPalette = {"blue",   "yellow", "pink", "green",
                                                  "orange", "cyan",   "red",  "white"};
inline constexpr int kBlue = 0, kYellow = 1, kPink = 2, kGreen = 3, kOrange = 4, kCyan = 5,
                     kRed = 6;

inline Pattern LoadPattern(const std::string& name) {
  return formats::LoadPatternFile(std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name + ".toml");
}

// A detector for one pattern with every ID of `id_colours` (or the given codebook).
inline DetectorPattern MakeDetectorPattern(const Pattern& pattern,
                                           const std::vector<std::string>& id_colours,
                                           double symmetry_tolerance_mm = 10.0) {
  DetectorPattern dp;
  dp.pattern = pattern;
  dp.symmetry_tolerance_mm = symmetry_tolerance_mm;
  dp.codebook = GenerateCodebook(pattern, FindSymmetry(pattern, symmetry_tolerance_mm), id_colours);
  dp.key_colours = {"blue", "yellow"};
  return dp;
}

inline DetectorConfig MakeConfig(std::vector<DetectorPattern> patterns,
                                 DetectorOptions options = {}) {
  DetectorConfig config;
  config.palette = kPalette;
  config.options = options;
  config.patterns = std::move(patterns);
  return config;
}

inline int Label(const std::string& name) {
  for (size_t i = 0; i < kPalette.size(); ++i) {
    if (kPalette[i] == name) return static_cast<int>(i);
  }
  return -1;
}

// The exact blobs of one robot wearing `entry` of `codebook`, appended to `blobs`.
inline void AddRobot(const Pattern& pattern, const Codebook& codebook, int entry, int team_label,
                     const Pose2& pose, std::vector<Blob>* blobs, int skip_patch = -1) {
  const std::vector<int> slots = IdSlots(pattern);
  for (int i = 0; i < pattern.size(); ++i) {
    if (i == skip_patch) continue;
    const Patch& patch = pattern.patches[i];
    int label = team_label;
    if (patch.role == PatchRole::kFixed) label = Label(patch.colour);
    if (patch.role == PatchRole::kId) {
      int slot = 0;
      while (slots[slot] != i) ++slot;
      label = Label(codebook.colours[codebook.entries[entry].colour[slot]]);
    }
    blobs->push_back(
        {pose.Apply(patch.position_mm), label, 3.14159 * patch.radius_mm * patch.radius_mm});
  }
}

inline Pose2 RandomPose(RandomStream& rng, double half_extent_mm = 2000.0) {
  return Pose2{rng.Uniform(-half_extent_mm, half_extent_mm),
               rng.Uniform(-half_extent_mm, half_extent_mm), rng.Uniform(-3.14159, 3.14159)};
}

}  // namespace patlab::detect::testing

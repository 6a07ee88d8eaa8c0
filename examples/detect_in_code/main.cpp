// detect_in_code: one SSL robot's blobs through a detector whose configuration is built in code,
// with the detection core alone (patlab::detect; no settings file, so no TOML parser and no image
// library).
//
//   detect_in_code
//
// The pattern is the SSL standard butterfly (patterns/ssl-standard.toml): a team-colour key disc
// of radius 25 mm at the origin and four ID dots of radius 20 mm, pink or green. Its IDs are
// generated (GenerateCodebook), not the league's codebook file. Prints one line per detection:
// team, id, status, x_mm, y_mm, theta_rad.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/codebook.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"

namespace {

patlab::Pattern SslPattern() {
  patlab::Pattern pattern;
  pattern.name = "ssl-standard";
  auto disc = [](double x, double y, double radius, patlab::PatchRole role) {
    patlab::Patch patch;
    patch.position_mm = patlab::Vec2(x, y);
    patch.radius_mm = radius;
    patch.role = role;
    return patch;
  };
  pattern.patches = {disc(0.0, 0.0, 25.0, patlab::PatchRole::kKey),
                     disc(35.0, 54.772, 20.0, patlab::PatchRole::kId),
                     disc(35.0, -54.772, 20.0, patlab::PatchRole::kId),
                     disc(-54.772, 35.0, 20.0, patlab::PatchRole::kId),
                     disc(-54.772, -35.0, 20.0, patlab::PatchRole::kId)};
  pattern.key_index = 0;
  pattern.orientation_pairs = patlab::DefaultOrientationPairs(pattern.patches, pattern.key_index);
  return pattern;
}

patlab::detect::DetectorConfig SslConfig() {
  patlab::detect::DetectorPattern dp;
  dp.pattern = SslPattern();
  dp.key_colours = {"blue", "yellow"};
  dp.codebook = patlab::detect::GenerateCodebook(
      dp.pattern, patlab::detect::FindSymmetry(dp.pattern, dp.symmetry_tolerance_mm),
      {"pink", "green"});
  return patlab::detect::MakeDetectorConfig({"blue", "yellow", "pink", "green"},
                                            patlab::detect::DetectorOptions{}, {dp});
}

}  // namespace

int main() {
  try {
    patlab::detect::Detector detector(SslConfig());
    const int blue = detector.ColourLabel("blue"), pink = detector.ColourLabel("pink"),
              green = detector.ColourLabel("green");
    // One frame's blobs: position on the floor (mm), colour label, area (mm^2).
    const std::vector<patlab::detect::Blob> blobs = {
        {patlab::Vec2(0.0, 0.0), blue, 1963.5},         // key patch, r = 25 mm
        {patlab::Vec2(35.0, 54.772), pink, 1256.6},     // front-left, r = 20 mm
        {patlab::Vec2(35.0, -54.772), pink, 1256.6},    // front-right
        {patlab::Vec2(-54.772, 35.0), green, 1256.6},   // back-left
        {patlab::Vec2(-54.772, -35.0), pink, 1256.6}};  // back-right
    std::vector<patlab::detect::Detection> detections;
    detector.Detect(blobs, &detections);
    const auto& config = detector.config();
    for (const patlab::detect::Detection& d : detections) {
      std::printf("%s %d %s %.2f %.2f %.4f\n", config.palette[d.team_colour].c_str(), d.id,
                  std::string(patlab::detect::DetectionStatusName(d.status)).c_str(), d.pose.x_mm,
                  d.pose.y_mm, d.pose.theta_rad);
    }
  } catch (const patlab::InputError& e) {
    std::cerr << "detect_in_code: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "detect_in_code: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

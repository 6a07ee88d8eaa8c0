// detect_blobs: detect robots in one frame from its blobs with patlab's detection core, as a
// robot's vision stack would after its own segmentation, configured by a detector settings file
// (read by the formats room; examples/detect_in_code builds the configuration in code instead).
//
//   detect_blobs SETTINGS.toml BLOBS.csv
//
// SETTINGS.toml is a patlab detector settings file (palette, [detector], [[pattern]] tables).
// BLOBS.csv has a header naming at least the columns colour, x_mm, y_mm and area_mm2 (the file
// `patlab detect FRAME --blobs` writes); colours not in the settings' palette are ignored.
// Prints one line per detection: pattern, team, id, status, x_mm, y_mm, theta_rad.
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/detect/detector.h"
#include "patlab/formats/detector_settings.h"

namespace {

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
  return cells;
}

// The blobs of a CSV file, colours mapped to the detector's palette labels.
std::vector<patlab::detect::Blob> ReadBlobs(const std::string& path,
                                            const patlab::detect::Detector& detector) {
  std::ifstream in(path);
  if (!in) throw patlab::InputError(path + ": cannot open");
  std::string line;
  if (!std::getline(in, line)) throw patlab::InputError(path + ": empty; expected a CSV header");
  const std::vector<std::string> header = SplitCsv(line);
  auto column = [&](const std::string& name) {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    throw patlab::InputError(path + ":1: no column '" + name + "'");
  };
  const size_t colour = column("colour"), x = column("x_mm"), y = column("y_mm"),
               area = column("area_mm2");
  std::vector<patlab::detect::Blob> blobs;
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    const std::vector<std::string> cells = SplitCsv(line);
    if (cells.size() != header.size()) {
      throw patlab::InputError(path + ":" + std::to_string(line_number) + ": " +
                               std::to_string(cells.size()) + " cells; expected " +
                               std::to_string(header.size()));
    }
    const int label = detector.ColourLabel(cells[colour]);
    if (label < 0) continue;
    blobs.push_back(
        {patlab::Vec2(std::stod(cells[x]), std::stod(cells[y])), label, std::stod(cells[area])});
  }
  return blobs;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: detect_blobs SETTINGS.toml BLOBS.csv\n";
    return 2;
  }
  try {
    patlab::detect::Detector detector(patlab::formats::LoadDetectorSettings(argv[1]));
    const std::vector<patlab::detect::Blob> blobs = ReadBlobs(argv[2], detector);
    std::vector<patlab::detect::Detection> detections;
    detector.Detect(blobs, &detections);
    const auto& config = detector.config();
    for (const patlab::detect::Detection& d : detections) {
      std::printf("%s %s %d %s %.2f %.2f %.4f\n", config.patterns[d.pattern].pattern.name.c_str(),
                  config.palette[d.team_colour].c_str(), d.id,
                  std::string(patlab::detect::DetectionStatusName(d.status)).c_str(), d.pose.x_mm,
                  d.pose.y_mm, d.pose.theta_rad);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "detect_blobs: " << e.what() << "\n";
    return 2;
  }
}

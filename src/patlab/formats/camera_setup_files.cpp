// The files of a setup folder and the text of setup's flags (formats/camera_setup.h): the
// folder's setup.toml, the landmark list, --landmark and --colour-option.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace fs = std::filesystem;

SetupFiles LoadSetupFiles(const std::string& dir) {
  const std::string path = (fs::path(dir) / "setup.toml").string();
  if (!fs::exists(path)) {
    throw InputError("--setup " + dir +
                     ": no setup.toml in it; expected a folder written by "
                     "patlab setup");
  }
  const toml::table root = io::ParseTomlFile(path);
  SetupFiles f;
  auto get = [&](const char* key) {
    const auto v = root[key].value<std::string>();
    if (!v) {
      throw InputError(path + ":1: missing or non-text key '" + key +
                       "'; expected calibration, thresholds and settings file names");
    }
    const fs::path p(*v);
    return (p.is_absolute() ? p : fs::path(dir) / p).string();
  };
  f.calibration = get("calibration");
  f.thresholds = get("thresholds");
  f.settings = get("settings");
  return f;
}

std::string LandmarkListText(const calib::Field& field) {
  std::string s = "landmarks of " + field.name + " (name, x mm, y mm):\n";
  for (const calib::FieldPoint& p : field.points) {
    s += "  " + p.name + " " + FormatNumber(p.at_mm.x()) + " " + FormatNumber(p.at_mm.y()) + "\n";
  }
  return s;
}

namespace {

std::optional<double> ParseDecimal(const std::string& text) {
  double value = 0.0;
  const char* begin = text.data() + (text.starts_with('+') ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

}  // namespace

SetupLandmark ParseLandmark(const std::string& text) {
  static const std::regex kForm(R"(^([A-Za-z0-9_]+)=([-+0-9.eE]+),([-+0-9.eE]+)$)");
  std::smatch m;
  const std::optional<double> x =
      std::regex_match(text, m, kForm) ? ParseDecimal(m[2].str()) : std::nullopt;
  const std::optional<double> y = x ? ParseDecimal(m[3].str()) : std::nullopt;
  if (!x || !y) {
    throw InputError("--landmark '" + text +
                     "'; expected NAME=X,Y (a landmark of the field and its pixel)");
  }
  return {m[1].str(), Vec2(*x, *y)};
}

void ParseColourOption(const std::string& text, vision::BlobThresholdsOptions* options) {
  static const std::regex kForm(R"(^([A-Za-z0-9_]+)=([-+0-9.eE]+)$)");
  std::smatch m;
  const std::optional<double> value =
      std::regex_match(text, m, kForm) ? ParseDecimal(m[2].str()) : std::nullopt;
  if (!value) {
    throw InputError("--colour-option '" + text +
                     "'; expected NAME=VALUE (an option of the colour fit and a number)");
  }
  try {
    vision::SetBlobThresholdsOption(m[1].str(), *value, options);
    vision::Validate(*options);
  } catch (const InputError& e) {
    throw InputError("--colour-option '" + text + "': " + e.what());
  }
}

}  // namespace patlab::formats

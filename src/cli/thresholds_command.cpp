// patlab thresholds: a labels file (an image, and per colour class sample points, rectangles or
// mask colours) -> a thresholds file for `patlab detect` (vision/thresholds_fit.h), with a report
// of each class's catches and the classes that overlap in colour space.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/data.h"
#include "patlab/core/enum_names.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/labels_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/thresholds_fit.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab thresholds my-labels.toml -o thresholds       # -> thresholds/thresholds.toml
  patlab thresholds labels.toml -o t --settings detector --margin 10

LABELS is a labels TOML file (docs/file-formats.md): the image, an optional label mask, and one
[[class]] per colour with sample points [x, y], rectangles [x0, y0, x1, y1] (pixels, inclusive)
and/or its colour in the mask. Each class's box spans the chosen percentiles of its samples per
channel, widened by --margin levels. The report lists per class its box, how many of its samples
the thresholds classify as it (recall), how many pixels labelled otherwise or unlabelled they also
catch, and every pair of overlapping boxes. With --settings every class must be a colour of the
detector's palette. Exit status: 0 ok, 1 cannot write the file, 2 bad input (nothing written).
)";

struct ThresholdsCommandOptions {
  std::string labels;
  std::string out;
  std::string settings;
  std::string space = "yuv";
  vision::ThresholdsFitOptions fit;
};

// A frame the labels file names, its errors put at the line that names it.
camera::Image ReadAt(const vision::Labels& labels, const std::string& path, int line,
                     const char* key) {
  try {
    return vision::ReadFrame(path);
  } catch (const InputError& e) {
    throw InputError(FileLoc{labels.source, line}, std::string(key) + ": " + e.what());
  }
}

}  // namespace

int RunThresholds(const std::vector<std::string>& args) {
  ThresholdsCommandOptions o;
  po::options_description visible("usage: patlab thresholds LABELS -o DIR [options]");
  visible.add_options()("help,h", "show this help")(
      "out,o", po::value(&o.out), "output directory: DIR/thresholds.toml (required)")(
      "settings,s", po::value(&o.settings),
      "detector settings: every class must be a colour of its palette")(
      "space", po::value(&o.space), "yuv (default, as CMVision) or rgb")(
      "lower-percentile", po::value(&o.fit.lower_percentile),
      "lower bound percentile of each channel, in [0, 50) (default 1)")(
      "upper-percentile", po::value(&o.fit.upper_percentile),
      "upper bound percentile of each channel, in (50, 100] (default 99)")(
      "margin", po::value(&o.fit.margin_levels),
      "levels added on each side of every bound, 0..128 (default 6)");
  po::variables_map vm;
  if (!ParseArguments(args, visible, "labels", po::value(&o.labels), 1, kExamples, &vm)) {
    return kExitOk;
  }
  if (o.labels.empty())
    throw InputError("missing LABELS; expected 'patlab thresholds LABELS.toml --out FILE'");
  if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
  o.out = (std::filesystem::path(o.out) / "thresholds.toml").string();
  const auto space = FindName(o.space, vision::kColorSpaceNames);
  if (!space) {
    throw InputError("--space is '" + EscapeForMessage(o.space) + "'; expected " +
                     NameList(vision::kColorSpaceNames));
  }
  o.fit.space = *space;
  vision::Validate(o.fit);
  io::CheckWritable({o.out});

  const vision::Labels labels = formats::LoadLabels(FindData(o.labels, io::DataKind::kSettings));
  if (!o.settings.empty()) {
    vision::CheckClassesKnown(
        labels,
        formats::LoadDetectorSettings(FindData(o.settings, io::DataKind::kSettings)).palette);
  }
  const camera::Image image = ReadAt(labels, labels.image_path, labels.image_line, "image");
  std::optional<camera::Image> mask;
  if (!labels.mask_path.empty()) {
    mask = ReadAt(labels, labels.mask_path, labels.mask_line, "mask");
  }
  const std::vector<int> pixel_labels =
      vision::LabelPixels(labels, image.width_px, image.height_px, mask ? &*mask : nullptr);
  const vision::ThresholdsFit fit = vision::FitThresholds(image, pixel_labels, labels, o.fit);
  const std::string text = vision::ThresholdsToml(
      fit.thresholds, "Made by patlab thresholds from " + labels.source + " (lower percentile " +
                          FormatNumber(o.fit.lower_percentile) + ", upper percentile " +
                          FormatNumber(o.fit.upper_percentile) + ", margin " +
                          std::to_string(o.fit.margin_levels) + " levels).");
  try {
    io::WriteFilesAtomic({{o.out, text}});
  } catch (const std::exception& e) {
    std::cerr << "patlab thresholds: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << vision::ThresholdsFitReport(fit) << "wrote " << o.out << "\n";
  return kExitOk;
}

PATLAB_REGISTER_COMMAND("thresholds", "fit colour thresholds to labelled sample pixels",
                        RunThresholds);

}  // namespace patlab::cli

// patlab thresholds: a labels file (an image, and per colour class sample points, rectangles or
// mask colours) -> a thresholds file for `patlab detect` (vision/thresholds_fit.h), with a report
// of each class's catches and the classes that overlap in colour space; with --auto, frames and
// the colour classes the patterns need -> thresholds found by clustering
// (vision/thresholds_auto.h), with a report of each class's cluster.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/core/enum_names.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/labels_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/thresholds_auto.h"
#include "patlab/vision/thresholds_fit.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kThresholdsExamples = R"(examples:
  patlab thresholds my-labels.toml -o thresholds       # -> thresholds/thresholds.toml
  patlab thresholds labels.toml -o t --settings detector --margin 10
  patlab thresholds --auto frame1.png frame2.png --settings detector -o t
  patlab thresholds --auto frame.png --classes blue,yellow,pink,green,orange -o t
  patlab thresholds --auto frame.png --settings detector --labels labels.toml -o t

LABELS is a labels TOML file (docs/file-formats.md): the image, an optional label mask, and one
[[class]] per colour with sample points [x, y], rectangles [x0, y0, x1, y1] (pixels, inclusive)
and/or its colour in the mask. Each class's box spans the chosen percentiles of its samples per
channel, widened by --margin levels. The report lists per class its box, how many of its samples
the thresholds classify as it (recall), how many pixels labelled otherwise or unlabelled they also
catch, and every pair of overlapping boxes. With --settings every class must be a colour of the
detector's palette.

With --auto the arguments are frames (files, folders or globs), and the classes are --classes (a
comma-separated list of names of the colour vocabulary, settings/colours.toml) or the palette of
--settings. The carpet is found as the dominant colour and each class by clustering the other
pixels around the vocabulary's colour (or the mean of the pixels --labels gives it), in hue and
saturation, which a change of light intensity leaves alone; the boxes are stretched for lighting
from --lighting-min-gain to --lighting-max-gain times the frames'. The report lists per class its
pixels, mean, spread, box and separability (distance to the nearest other class in units of
spread). Exit status: 0 ok, 1 cannot write the file, 2 bad input (nothing written).
)";

struct ThresholdsCommandOptions {
  std::string labels;
  std::string out;
  std::string settings;
  std::string space = "yuv";
  vision::ThresholdsFitOptions fit;
  bool automatic = false;
  std::vector<std::string> inputs;  // LABELS, or the frames with --auto
  std::string classes;
  std::string colours;
  std::vector<std::string> labels_files;
  vision::AutoThresholdsOptions auto_fit;
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

// The class names of --auto: --classes, else the palette of --settings.
std::vector<std::string> AutoClasses(const ThresholdsCommandOptions& o) {
  if (!o.classes.empty() && !o.settings.empty()) {
    throw InputError("--classes and --settings both given; expected one of them with --auto");
  }
  if (!o.settings.empty()) {
    return formats::LoadDetectorSettings(FindData(o.settings, io::DataKind::kSettings)).palette;
  }
  if (o.classes.empty()) {
    throw InputError("--auto without --classes or --settings; expected the colour classes");
  }
  std::vector<std::string> names;
  size_t start = 0;
  while (start <= o.classes.size()) {
    const size_t comma = std::min(o.classes.find(',', start), o.classes.size());
    names.push_back(o.classes.substr(start, comma - start));
    start = comma + 1;
  }
  return names;
}

int RunAuto(const ThresholdsCommandOptions& o) {
  const ColourVocabulary vocabulary =
      o.colours.empty() ? io::DefaultColourVocabulary()
                        : io::LoadColourVocabulary(FindData(o.colours, io::DataKind::kSettings));
  std::vector<std::string> classes = AutoClasses(o);
  for (std::string& name : classes) {
    const ColourResolution r = ResolveColourName(vocabulary, name);
    if (!r.known) throw InputError("--classes: " + UnknownColourMessage(vocabulary, r));
    name = r.name;
  }
  const std::vector<std::string> paths = vision::ExpandFrameList(o.inputs);
  std::vector<camera::Image> frames;
  for (const std::string& path : paths) frames.push_back(vision::ReadFrame(path));
  std::vector<const camera::Image*> frame_pointers;
  for (const camera::Image& f : frames) frame_pointers.push_back(&f);
  // Labels files, pooled: each names its own frame.
  std::vector<camera::Image> labelled_images;
  std::vector<vision::Labels> labels_read;
  labelled_images.reserve(o.labels_files.size());
  std::vector<vision::LabelledFrame> labelled;
  for (const std::string& file : o.labels_files) {
    labels_read.push_back(formats::LoadLabels(FindData(file, io::DataKind::kSettings)));
    const vision::Labels& l = labels_read.back();
    labelled_images.push_back(ReadAt(l, l.image_path, l.image_line, "image"));
    const camera::Image& image = labelled_images.back();
    std::optional<camera::Image> mask;
    if (!l.mask_path.empty()) mask = ReadAt(l, l.mask_path, l.mask_line, "mask");
    vision::LabelledFrame lf;
    lf.image = &image;
    lf.labels = vision::LabelPixels(l, image.width_px, image.height_px, mask ? &*mask : nullptr);
    for (const vision::LabelClass& c : l.classes) lf.class_names.push_back(c.name);
    labelled.push_back(std::move(lf));
  }
  const vision::AutoThresholdsFit fit =
      vision::FitThresholdsAuto(frame_pointers, classes, vocabulary, o.auto_fit, labelled);
  std::string comment =
      "Made by patlab thresholds --auto from " + std::to_string(paths.size()) + " frame(s)" +
      (o.labels_files.empty()
           ? std::string()
           : " and " + std::to_string(o.labels_files.size()) + " labels file(s)") +
      " (lighting gain " + FormatNumber(o.auto_fit.lighting_min_gain) + " to " +
      FormatNumber(o.auto_fit.lighting_max_gain) + ", margin " +
      std::to_string(o.auto_fit.margin_levels) + " levels).";
  const std::string text = vision::ThresholdsToml(fit.thresholds, comment);
  try {
    io::WriteFilesAtomic({{o.out, text}});
  } catch (const std::exception& e) {
    std::cerr << "patlab thresholds: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << vision::AutoThresholdsReport(fit) << "wrote " << o.out << "\n";
  return kExitOk;
}

}  // namespace

namespace {

// LABELS -> thresholds (the labelled fit, thresholds_fit.h).
int RunLabelled(ThresholdsCommandOptions* o) {
  if (o->inputs.size() > 1) {
    throw InputError("more than one LABELS file; expected one (several frames: --auto)");
  }
  if (!o->inputs.empty()) o->labels = o->inputs.front();
  if (o->labels.empty())
    throw InputError("missing LABELS; expected 'patlab thresholds LABELS.toml --out DIR'");
  if (o->out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
  o->out = (std::filesystem::path(o->out) / "thresholds.toml").string();
  const auto space = FindName(o->space, vision::kColorSpaceNames);
  if (!space) {
    throw InputError("--space is '" + EscapeForMessage(o->space) + "'; expected " +
                     NameList(vision::kColorSpaceNames));
  }
  o->fit.space = *space;
  vision::Validate(o->fit);
  io::CheckWritable({o->out});

  const vision::Labels labels = formats::LoadLabels(FindData(o->labels, io::DataKind::kSettings));
  if (!o->settings.empty()) {
    vision::CheckClassesKnown(
        labels,
        formats::LoadDetectorSettings(FindData(o->settings, io::DataKind::kSettings)).palette);
  }
  const camera::Image image = ReadAt(labels, labels.image_path, labels.image_line, "image");
  std::optional<camera::Image> mask;
  if (!labels.mask_path.empty()) {
    mask = ReadAt(labels, labels.mask_path, labels.mask_line, "mask");
  }
  const std::vector<int> pixel_labels =
      vision::LabelPixels(labels, image.width_px, image.height_px, mask ? &*mask : nullptr);
  const vision::ThresholdsFit fit = vision::FitThresholds(image, pixel_labels, labels, o->fit);
  const std::string text = vision::ThresholdsToml(
      fit.thresholds, "Made by patlab thresholds from " + labels.source + " (lower percentile " +
                          FormatNumber(o->fit.lower_percentile) + ", upper percentile " +
                          FormatNumber(o->fit.upper_percentile) + ", margin " +
                          std::to_string(o->fit.margin_levels) + " levels).");
  try {
    io::WriteFilesAtomic({{o->out, text}});
  } catch (const std::exception& e) {
    std::cerr << "patlab thresholds: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << vision::ThresholdsFitReport(fit) << "wrote " << o->out << "\n";
  return kExitOk;
}

}  // namespace

// The help's option groups (command_line.h).
const OptionGroups kThresholdsGroups = {
    {"input", {"settings"}},
    {"fit", {"space", "lower-percentile", "upper-percentile", "margin"}},
    {"automatic fit",
     {"auto", "classes", "labels", "colours", "lighting-min-gain", "lighting-max-gain"}}};

int RunThresholds(const std::vector<std::string>& args) {
  ThresholdsCommandOptions o;
  po::options_description visible(
      "usage: patlab thresholds LABELS -o DIR [options]\n"
      "       patlab thresholds --auto FRAME... (--classes NAMES | -s SETTINGS) -o DIR [options]");
  visible.add_options()("help,h", "show this help")(
      "out,o", po::value(&o.out), "output directory: DIR/thresholds.toml (required)")(
      "settings,s", po::value(&o.settings),
      "detector settings: every class must be a colour of its palette (--auto: the "
      "classes are its palette)")("space", po::value(&o.space),
                                  "yuv (default, as CMVision) or rgb")(
      "lower-percentile", po::value(&o.fit.lower_percentile),
      "lower bound percentile of each channel, in [0, 50) (default 1; 2 with --auto)")(
      "upper-percentile", po::value(&o.fit.upper_percentile),
      "upper bound percentile of each channel, in (50, 100] (default 99; 98 with --auto)")(
      "margin", po::value(&o.fit.margin_levels),
      "levels added on each side of every bound, 0..128 (default 6; 4 with --auto)")(
      "auto", po::bool_switch(&o.automatic),
      "find the thresholds in FRAME... by clustering, with no labels")(
      "classes", po::value(&o.classes),
      "--auto: the colour classes, comma-separated names of the colour vocabulary")(
      "labels", po::value(&o.labels_files)->multitoken(),
      "--auto: labels files whose labelled pixels seed their classes (pooled)")(
      "colours", po::value(&o.colours),
      "--auto: the colour vocabulary, a file or a name (default: the shipped colours)")(
      "lighting-min-gain", po::value(&o.auto_fit.lighting_min_gain),
      "--auto: darkest light the boxes must hold for, relative to the frames', (0, 1] (default "
      "0.7)")("lighting-max-gain", po::value(&o.auto_fit.lighting_max_gain),
              "--auto: brightest light, [1, 4] (default 1.4)");
  po::variables_map vm;
  if (!ParseArguments(args, visible, kThresholdsGroups, "inputs", po::value(&o.inputs), -1,
                      kThresholdsExamples, &vm)) {
    return kExitOk;
  }
  ThrowFlagProblem(vision::Check(o.fit), vm,
                   {{"lower_percentile", "--lower-percentile"},
                    {"upper_percentile", "--upper-percentile"},
                    {"margin_levels", "--margin"}});
  if (o.automatic) {
    if (o.inputs.empty()) throw InputError("--auto without frames; expected FRAME...");
    if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
    o.out = (std::filesystem::path(o.out) / "thresholds.toml").string();
    if (vm.count("margin")) o.auto_fit.margin_levels = o.fit.margin_levels;
    if (vm.count("lower-percentile")) o.auto_fit.lower_percentile = o.fit.lower_percentile;
    if (vm.count("upper-percentile")) o.auto_fit.upper_percentile = o.fit.upper_percentile;
    vision::Validate(o.auto_fit);
    io::CheckWritable({o.out});
    return RunAuto(o);
  }
  for (const char* flag :
       {"classes", "labels", "colours", "lighting-min-gain", "lighting-max-gain"}) {
    if (vm.count(flag)) {
      throw InputError(std::string("--") + flag + " without --auto; expected it with --auto");
    }
  }
  return RunLabelled(&o);
}

PATLAB_REGISTER_COMMAND("thresholds", "fit colour thresholds to labelled sample pixels",
                        RunThresholds);

}  // namespace patlab::cli

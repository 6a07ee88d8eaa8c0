// patlab setup: a new camera from its frames -- the calibration from the field's lines, the
// colour thresholds from the settings' palette, the detector's tolerances from what was measured
// (formats/camera_setup.h) -- written into one folder that `patlab detect --setup DIR` reads.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;

constexpr const char* kSetupExamples = R"(examples:
  patlab setup frame.png --field ssl --settings ssl-frame.detector -o cam
  patlab detect frame.png --setup cam
  patlab setup frame.png --field vss --settings my-vss.toml --robot-height 75 -o cam
  patlab setup frame.png --field ssl-2009 --settings S -o cam \
      --landmark centre=390,290 --landmark corner_pos_left=700,40 ...
  patlab setup --list-landmarks ssl-2009

FIELD is a field model (patlab fields) or a family (ssl, vss): with a family every model is
screened against the first frame's lines, the best few are fitted and the one explaining the
most line length is kept. The
settings (a shipped name or a file) give the palette and the patterns; their [detector]
tolerances are replaced by the ones setup chooses. DIR receives calibration.toml,
thresholds.toml, settings.toml and setup.toml (docs/setup.md). Exit status: 0 ok, 2 bad input or
frames that do not decide the camera, 1 the folder could not be written.
)";

struct SetupCommandOptions {
  std::vector<std::string> frames;
  std::string field, settings, out, list_landmarks;
  std::vector<std::string> landmarks, colour_options;
  double robot_height_mm = 140.0;
  double camera_height_mm = 0.0;
  double line_width_px = 4.0;
  int binning = 0;
  bool explain = false;
};

const OptionGroups kSetupGroups = {
    {"input",
     {"field", "settings", "robot-height", "camera-height", "line-width", "binning", "landmark"}},
    {"colour fit", {"colour-option"}},
    {"output", {"out"}},
    {"diagnostics", {"explain"}},
    {"field models", {"list-landmarks"}}};

// The robots each frame shows, through the files just written (read back as detect reads them);
// with `explain`, every key candidate's diagnosis as patlab detect --explain prints it.
void PrintDetections(const fs::path& dir, const std::vector<camera::Image>& frames,
                     const std::vector<std::string>& names, bool explain) {
  const formats::SetupFiles f = formats::LoadSetupFiles(dir.string());
  vision::FrameDetectorOptions options;
  options.explain = explain;
  vision::ApplyFrameSettings(formats::LoadFrameSettings(f.settings), &options);
  vision::FrameDetector detector(formats::LoadThresholds(f.thresholds),
                                 formats::LoadCalibration(f.calibration),
                                 formats::LoadDetectorSettings(f.settings), options);
  for (const std::string& w : detector.warnings()) std::cout << "warning: " << w << "\n";
  const std::vector<std::string>& palette = detector.detector().config().palette;
  for (size_t i = 0; i < frames.size(); ++i) {
    const vision::FrameResult& r = detector.Detect(frames[i], names[i]);
    std::cout << "robots in " << names[i] << ": " << r.detections.size() << "\n";
    for (const detect::Detection& d : r.detections) {
      const std::string team =
          d.team_colour >= 0 ? palette[static_cast<size_t>(d.team_colour)] : "?";
      std::cout << "  " << team << " " << d.id << " at (" << FormatFixed(d.pose.x_mm, 0) << ", "
                << FormatFixed(d.pose.y_mm, 0) << ") mm\n";
    }
    std::cout << vision::ExplanationText(r, detector);
  }
}

// The library's options from the command's flags.
formats::SetupOptions OptionsOf(const SetupCommandOptions& o) {
  formats::SetupOptions options;
  formats::SetupFieldModels models = formats::SetupFields(o.field, DataRoots());
  options.fields = std::move(models.fields);
  options.lenders = std::move(models.lenders);
  options.settings_path = FindData(o.settings, io::DataKind::kSettings);
  options.robot_height_mm = o.robot_height_mm;
  if (o.camera_height_mm < 0.0)
    throw InputError("--camera-height: negative; expected mm above the floor, or 0 for unknown");
  if (o.camera_height_mm > 0.0) options.camera_height_mm = o.camera_height_mm;
  options.line_width_px = o.line_width_px;
  options.binning = o.binning;
  for (const std::string& l : o.landmarks) options.landmarks.push_back(formats::ParseLandmark(l));
  for (const std::string& c : o.colour_options) formats::ParseColourOption(c, &options.colours);
  return options;
}

int RunSetup(const std::vector<std::string>& args) {
  SetupCommandOptions o;
  po::options_description visible(
      "usage: patlab setup FRAME... --field FIELD|FAMILY --settings S -o DIR [options]\n"
      "       patlab setup --list-landmarks FIELD");
  visible.add_options()("help,h", "show this help")(
      "field", po::value(&o.field),
      "the field model (fitted alone, the rest of its family lending views) or family (ssl, vss) "
      "(required)")("settings,s", po::value(&o.settings),
                    "detector settings: palette and patterns (a shipped name or a file; required)")(
      "robot-height", po::value(&o.robot_height_mm)->default_value(140.0),
      "the patterns' plane above the floor (mm), in [0, 1000]")(
      "camera-height", po::value(&o.camera_height_mm)->default_value(0.0),
      "the camera's measured height above the floor (mm; 0 = unknown: the lines, or the robots "
      "where the lines leave it open, decide)")(
      "line-width", po::value(&o.line_width_px)->default_value(4.0),
      "the field lines' width in the frames as setup works on them (binned, px), in [1, 30]")(
      "binning", po::value(&o.binning)->default_value(0),
      "bin the frames K x K before setting up, and detect likewise (0 = from their size: frames "
      "over 1024 px along their longer side are binned to that or below)")(
      "landmark", po::value(&o.landmarks),
      "NAME=X,Y: a landmark of the field at pixel (X, Y) of the first frame; four or more "
      "replace the lines (repeat the flag)")(
      "colour-option", po::value(&o.colour_options),
      "NAME=VALUE: an option of the colour fit (docs/setup.md lists them, with their defaults; "
      "repeat the flag)")("out,o", po::value(&o.out), "output folder (required)")(
      "explain", po::bool_switch(&o.explain),
      "after the robots, every key candidate and why it is a robot or not, with the setting "
      "change that would accept it (as patlab detect --explain)")(
      "list-landmarks", po::value(&o.list_landmarks),
      "print the landmark names of a field model and exit");
  po::variables_map vm;
  if (!ParseArguments(args, visible, kSetupGroups, "frames", po::value(&o.frames), -1,
                      kSetupExamples, &vm)) {
    return kExitOk;
  }
  if (!o.list_landmarks.empty()) {
    std::cout << formats::LandmarkListText(
        formats::LoadField(FindData(o.list_landmarks, io::DataKind::kField)));
    return kExitOk;
  }
  if (o.frames.empty()) throw InputError("no frames; expected 'patlab setup FRAME...'");
  if (o.field.empty()) throw InputError("missing --field; expected a field model or family");
  if (o.settings.empty())
    throw InputError("missing --settings; expected detector settings naming the patterns");
  if (o.out.empty()) throw InputError("missing --out DIR; expected the folder to write to");
  const formats::SetupOptions options = OptionsOf(o);
  const fs::path dir(o.out);
  io::CheckWritable({(dir / "setup.toml").string()});
  const std::vector<std::string> paths = vision::ExpandFrameList(o.frames);
  std::vector<camera::Image> frames;
  std::vector<std::string> names;
  for (const std::string& p : paths) {
    frames.push_back(vision::ReadFrame(p));
    names.push_back(fs::path(p).filename().string());
  }
  std::vector<const camera::Image*> pointers;
  for (const camera::Image& f : frames) pointers.push_back(&f);
  const formats::SetupResult r = formats::SetupCamera(pointers, names, options);
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, text] : r.files) files.emplace_back((dir / name).string(), text);
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& e) {
    std::cerr << "patlab setup: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << formats::SetupReportText(r);
  PrintDetections(dir, frames, names, o.explain);
  std::cout << "wrote " << (dir / "setup.toml").string()
            << " (calibration.toml, thresholds.toml, settings.toml)\n";
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("setup",
                        "set up a new camera from its frames: calibration, colours, "
                        "tolerances",
                        RunSetup);

}  // namespace patlab::cli

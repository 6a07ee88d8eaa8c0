// patlab calibrate: measured pixels of known field points, lines, circles and patterns -> a
// fitted pinhole camera (calib/calibrate.h), written as the calibration file `patlab detect`
// reads, with the fit's residuals in px and mm on every plane.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/calib/calibrate.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_input.h"
#include "patlab/formats/field_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"
#include "patlab/vision/field_lines.h"
#include "patlab/vision/frame_io.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kCalibrateExamples = R"(examples:
  patlab calibrate ssl-2008.calibration-input -o cal    # -> cal/calibration.toml, cal/residuals.csv
  patlab calibrate my-camera.toml -o cal
  patlab calibrate frame.png --auto --field ssl-2009 -o cal --debug

INPUT is a calibration-input TOML file (docs/calibrate.md): the image size, [[point]] tables
(a pixel and the field point it shows), [[line]] and [[circle]] tables (pixels anywhere on a known
field line or circle; the shipped fields experiments/fields/*.toml name them), [[pattern]] tables
(the patch pixels of a pattern of known layout at a known height), what to hold fixed ([fit]) and
the plane height of each colour class ([heights]). At least 4 known points on one plane start the
fit. The report gives each parameter's standard error and the residuals in px and, back-projected,
in mm on each plane. Exit status: 0 ok, 1 cannot write the files, 2 bad input.

With --auto, INPUT is a frame (PNG, JPEG, PPM) and nobody clicks: the white field lines are found
in it, matched to the field's lines and circles (--field, a shipped name or a file) and the camera
is fitted to them (docs/calibrate.md, "Automatic calibration from the field lines"). Writes
DIR/calibration.toml, DIR/residuals.csv, DIR/report.txt (what was found, which of the field's
equivalent views was chosen, the held-out mapping error in mm) and, with --debug,
DIR/lines.png (the line pixels in red, the fitted field in cyan). A frame whose lines do not
decide the camera is refused (exit 2) and nothing is written.
)";

struct CalibrateCommandOptions {
  std::string input;
  std::string out;
  std::string residuals;
  bool automatic = false;
  std::string field;
  bool debug = false;
  double line_width_px = 4.0;
  double camera_height_mm = 0.0;
};

std::string ResidualsCsv(const calib::CalibrationFit& fit) {
  std::string out = "kind,name,pixel,source,height_mm,px,mm\n";
  for (const calib::ObservationResidual& r : fit.residuals) {
    io::CsvWriter(&out)
        .Cells({r.kind, r.name, std::to_string(r.index + 1), r.loc.ToString(),
                FormatRoundTrip(r.height_mm), FormatSignificant(r.px, 6),
                FormatSignificant(r.mm, 6)})
        .EndRow();
  }
  return out;
}

// The help's option groups (command_line.h).
const OptionGroups kCalibrateGroups = {
    {"automatic calibration", {"auto", "field", "line-width", "camera-height", "debug"}}};

// --auto: the frame's field lines -> the calibration (vision/field_lines.h).
int RunAuto(const CalibrateCommandOptions& o) {
  if (o.field.empty()) throw InputError("--auto: missing --field; expected a field name or file");
  if (o.camera_height_mm < 0.0)
    throw InputError("--camera-height: negative; expected mm above the floor, or 0 for unknown");
  // A family's name that names no model of it nor a file ("ssl"; "vss" is a model too).
  const auto family = formats::FieldFamily(o.field, DataRoots());
  std::string models;
  bool a_model = std::filesystem::exists(o.field);
  for (const calib::Field& f : family) {
    models += (models.empty() ? "" : ", ") + f.name;
    a_model = a_model || f.name == o.field;
  }
  if (!family.empty() && !a_model) {
    throw InputError("--field " + o.field + ": a family of field models (" + models +
                     "); calibrate --auto fits one: expected one of them, or fit the family with "
                     "patlab setup --field " +
                     o.field);
  }
  const calib::Field field = formats::LoadField(FindData(o.field, io::DataKind::kField));
  const camera::Image frame = vision::ReadFrame(o.input);
  vision::LineFinderOptions finder;
  finder.line_width_px = o.line_width_px;
  calib::AutoOptions options;
  if (o.camera_height_mm > 0.0) options.camera_height_mm = o.camera_height_mm;
  const std::string name = std::filesystem::path(o.input).filename().string();
  const vision::FrameCalibration fc =
      vision::AutoCalibrateFrame(frame, name, field, finder, options);
  const calib::AutoCalibration& a = fc.calibration;
  const std::filesystem::path dir(o.out);
  const std::string report = calib::AutoReportText(a);
  std::vector<std::pair<std::string, std::string>> files = {
      {(dir / "calibration.toml").string(), calib::CalibrationFileText(a.input, a.fit)},
      {(dir / "residuals.csv").string(), ResidualsCsv(a.fit)},
      {(dir / "report.txt").string(), report}};
  try {
    io::WriteFilesAtomic(files);
    if (o.debug) {
      vision::WritePng(vision::DrawLinePixels(frame, fc.pixels, &field, &a),
                       (dir / "lines.png").string());
    }
  } catch (const InputError& e) {
    std::cerr << "patlab calibrate: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << report << "line finding: " << FormatSignificant(fc.find_seconds, 3)
            << " s; matching and fit: " << FormatSignificant(a.seconds, 3) << " s\n"
            << "wrote " << (dir / "calibration.toml").string() << "\n";
  return kExitOk;
}

int RunCalibrate(const std::vector<std::string>& args) {
  CalibrateCommandOptions o;
  po::options_description visible("usage: patlab calibrate INPUT -o DIR");
  visible.add_options()("help,h", "show this help")(
      "out,o", po::value(&o.out),
      "output directory: DIR/calibration.toml and DIR/residuals.csv (required)")(
      "auto", po::bool_switch(&o.automatic),
      "INPUT is a frame: find its field lines and fit the camera to them")(
      "field", po::value(&o.field), "with --auto: the field (a shipped name or a file; required)")(
      "line-width", po::value(&o.line_width_px)->default_value(4.0),
      "with --auto: the lines' width in the image (px), in [1, 30]")(
      "camera-height", po::value(&o.camera_height_mm)->default_value(0.0),
      "with --auto: the camera's measured height above the floor (mm; 0 = unknown)")(
      "debug", po::bool_switch(&o.debug), "with --auto: also write DIR/lines.png");
  po::variables_map vm;
  if (!ParseArguments(args, visible, kCalibrateGroups, "input", po::value(&o.input), 1,
                      kCalibrateExamples, &vm,
                      {{"--residuals", "-o DIR (DIR/residuals.csv is always written)"}})) {
    return kExitOk;
  }
  if (o.input.empty()) throw InputError("missing INPUT; expected 'patlab calibrate INPUT -o DIR'");
  if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
  if (!o.automatic && (!o.field.empty() || o.debug))
    throw InputError("--field and --debug: only with --auto; expected --auto FRAME");
  if (o.automatic) return RunAuto(o);
  o.residuals = (std::filesystem::path(o.out) / "residuals.csv").string();
  o.out = (std::filesystem::path(o.out) / "calibration.toml").string();

  const calib::CalibrationInput input =
      formats::LoadCalibrationInput(FindData(o.input, io::DataKind::kSettings));
  const calib::CalibrationFit fit = calib::FitCamera(input);
  std::vector<std::pair<std::string, std::string>> files = {
      {o.out, calib::CalibrationFileText(input, fit)}};
  if (!o.residuals.empty()) files.emplace_back(o.residuals, ResidualsCsv(fit));
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& e) {
    std::cerr << "patlab calibrate: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << calib::FitReportText(input, fit) << "wrote " << o.out
            << (o.residuals.empty() ? "" : " and " + o.residuals) << "\n";
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("calibrate", "fit a camera to known field points, lines and patterns",
                        RunCalibrate);

}  // namespace patlab::cli

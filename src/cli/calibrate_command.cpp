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
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab calibrate ssl-2008.calibration-input -o cal    # -> cal/calibration.toml, cal/residuals.csv
  patlab calibrate my-camera.toml -o cal

INPUT is a calibration-input TOML file (docs/calibrate.md): the image size, [[point]] tables
(a pixel and the field point it shows), [[line]] and [[circle]] tables (pixels anywhere on a known
field line or circle; the shipped fields experiments/fields/*.toml name them), [[pattern]] tables
(the patch pixels of a pattern of known layout at a known height), what to hold fixed ([fit]) and
the plane height of each colour class ([heights]). At least 4 known points on one plane start the
fit. The report gives each parameter's standard error and the residuals in px and, back-projected,
in mm on each plane. Exit status: 0 ok, 1 cannot write the files, 2 bad input.
)";

struct CalibrateCommandOptions {
  std::string input;
  std::string out;
  std::string residuals;
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
const OptionGroups kCalibrateGroups = {};

int RunCalibrate(const std::vector<std::string>& args) {
  CalibrateCommandOptions o;
  po::options_description visible("usage: patlab calibrate INPUT -o DIR");
  visible.add_options()("help,h", "show this help")(
      "out,o", po::value(&o.out),
      "output directory: DIR/calibration.toml and DIR/residuals.csv (required)");
  po::variables_map vm;
  if (!ParseArguments(args, visible, kCalibrateGroups, "input", po::value(&o.input), 1, kExamples,
                      &vm, {{"--residuals", "-o DIR (DIR/residuals.csv is always written)"}})) {
    return kExitOk;
  }
  if (o.input.empty()) throw InputError("missing INPUT; expected 'patlab calibrate INPUT -o DIR'");
  if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
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

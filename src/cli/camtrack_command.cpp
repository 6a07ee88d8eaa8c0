// patlab camtrack: the section-II track through the colour camera (analysis/camera_track.h): one
// pattern on the platform path, every frame rendered (a window around the pattern) by
// render/camera_render.h and measured by the real-frame colour segmentation; per colour group the
// std of the patch errors and the pattern's pose error, with 95% intervals, as CSV.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "patlab/analysis/camera_track.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kCamtrackExamples = R"(examples:
  patlab camtrack track-scene -t track.thresholds --label full -o full   # -> full/camtrack.csv
  patlab camtrack track-scene -t track.thresholds --read-noise-levels 0 \
      --shot-noise-gain 0 --no-bayer --chroma-444 --white --label quant -o quant

The SCENE file (docs/render.md) gives the pattern, codebook, colours, render options and the
calibration (the camera); its robots are ignored: one robot (--team, --id) rides the path.
CSV columns: label, group (key, id, all, pose; detect with --detect), samples, sx_mm, sx_lo, sx_hi,
sy_mm, sy_lo, sy_hi, stheta_rad, stheta_lo, stheta_hi, missed_patches, frames, tau_x, tau_y,
tau_theta (variance inflation of the correlated frames; the intervals use dof / tau),
detected_frames, wrong_id_frames. Docs: docs/render.md#camera-track.
Exit status: 0 ok, 1 cannot write the file, 2 bad input.
)";

struct Options {
  std::string scene, thresholds, out, label = "run", team = "blue";
  int id = 0;
  std::string seed = "14", sensor_seed = "1", jitter_seed = "1";
  bool no_bayer = false, chroma_444 = false;
  render::CameraSensorOptions sensor;
  render::CameraJitter jitter;
  analysis::CameraTrackOptions track;
  double blur_sigma_px = -1.0;
  bool quiet = false;
};

void AddOptions(po::options_description* d, Options* o) {
  d->add_options()("help,h", "show this help")("out,o", po::value(&o->out),
                                               "output directory: DIR/camtrack.csv (required)")(
      "thresholds,t", po::value(&o->thresholds), "colour thresholds TOML (required)")(
      "label", po::value(&o->label), "the label column, default run")(
      "team", po::value(&o->team), "team (key) colour, default blue")(
      "id", po::value(&o->id), "the codebook ID worn, default 0")(
      "white", po::bool_switch(&o->track.all_white), "every patch white (class white)")(
      "detect", po::bool_switch(&o->track.detect),
      "also measure the pattern through the detector (group detect)")(
      "runs", po::value(&o->track.runs), "runs, default 5")("frames", po::value(&o->track.frames),
                                                            "frames per run, default 2570")(
      "seed", po::value(&o->seed), "path seed (offsets, headings), default 14")(
      "blur-sigma-px", po::value(&o->blur_sigma_px), "optics blur, default the scene's")(
      "exposure-gain", po::value(&o->sensor.exposure_gain), "(0, 16], default 1")(
      "read-noise-levels", po::value(&o->sensor.read_noise_levels), "[0, 64], default 2")(
      "shot-noise-gain", po::value(&o->sensor.shot_noise_gain), "[0, 4], default 0.05")(
      "no-bayer", po::bool_switch(&o->no_bayer), "a three-chip camera")(
      "chroma-444", po::bool_switch(&o->chroma_444), "full-resolution colour, not 4:2:2")(
      "sensor-seed", po::value(&o->sensor_seed), "default 1")(
      "roll-jitter-rad", po::value(&o->jitter.roll_sigma_rad), "[0, 0.1], default 0")(
      "height-jitter-mm", po::value(&o->jitter.height_sigma_mm), "[0, 1000], default 0")(
      "shift-jitter-mm", po::value(&o->jitter.shift_sigma_mm), "[0, 1000], default 0")(
      "jitter-seed", po::value(&o->jitter_seed), "default 1");
  AddQuiet(d->add_options(), &o->quiet);
}

std::string Csv(const std::string& label, const analysis::CameraTrackResult& r) {
  std::string csv =
      "label,group,samples,sx_mm,sx_lo,sx_hi,sy_mm,sy_lo,sy_hi,stheta_rad,stheta_lo,stheta_hi,"
      "missed_patches,frames,tau_x,tau_y,tau_theta,detected_frames,wrong_id_frames\n";
  for (const analysis::GroupError& g : r.groups) {
    io::CsvWriter(&csv).Cells({label, g.group, std::to_string(g.samples)});
    for (double v :
         {g.sx, g.sx_lo, g.sx_hi, g.sy, g.sy_lo, g.sy_hi, g.stheta, g.stheta_lo, g.stheta_hi}) {
      csv.append(",").append(FormatSignificant(v, 6));
    }
    csv.append(",").append(std::to_string(r.missed_patches));
    csv.append(",").append(std::to_string(r.frames));
    for (double v : {g.tau_x, g.tau_y, g.tau_theta})
      csv.append(",").append(FormatSignificant(v, 4));
    csv.append(",").append(std::to_string(r.detected_frames));
    csv.append(",").append(std::to_string(r.wrong_id_frames)).append("\n");
  }
  return csv;
}

// The help's option groups (command_line.h).
const OptionGroups kCamtrackGroups = {
    {"input", {"thresholds"}},
    {"robot and path", {"team", "id", "white", "runs", "frames", "seed", "detect"}},
    {"camera",
     {"blur-sigma-px", "exposure-gain", "read-noise-levels", "shot-noise-gain", "no-bayer",
      "chroma-444", "sensor-seed"}},
    {"camera jitter", {"roll-jitter-rad", "height-jitter-mm", "shift-jitter-mm", "jitter-seed"}},
    {"output", {"out", "label"}}};

int RunCamtrack(const std::vector<std::string>& args) {
  Options o;
  po::options_description visible("usage: patlab camtrack SCENE -t THRESHOLDS -o DIR [options]");
  AddOptions(&visible, &o);
  po::variables_map vm;
  if (!ParseArguments(args, visible, kCamtrackGroups, "scene", po::value(&o.scene), 1,
                      kCamtrackExamples, &vm)) {
    return kExitOk;
  }
  if (o.scene.empty()) throw InputError("missing SCENE; expected a scene TOML file");
  ThrowCameraFlagProblem(o.sensor, o.jitter, vm);
  ThrowFlagProblem(analysis::Check(o.track), vm, {{"runs", "--runs"}, {"frames", "--frames"}});
  if (o.thresholds.empty()) throw InputError("missing --thresholds; expected a thresholds file");
  if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
  o.out = (std::filesystem::path(o.out) / "camtrack.csv").string();
  o.sensor.bayer = !o.no_bayer;
  o.sensor.chroma_422 = !o.chroma_444;
  o.sensor.seed = ParseSeed(o.sensor_seed, "--sensor-seed");
  o.jitter.seed = ParseSeed(o.jitter_seed, "--jitter-seed");
  o.track.seed = ParseSeed(o.seed, "--seed");
  io::CheckWritable({o.out});
  Progress progress("patlab camtrack", "frames", !o.quiet, StderrIsTerminal());
  o.track.progress = progress.Callback();
  formats::SceneFile file = formats::LoadSceneFile(FindData(o.scene, io::DataKind::kSettings));
  if (vm.count("blur-sigma-px")) file.scene.options.blur_sigma_px = o.blur_sigma_px;
  const vision::Thresholds thresholds =
      formats::LoadThresholds(FindData(o.thresholds, io::DataKind::kSettings));
  const analysis::CameraTrackResult r = analysis::RunCameraTrack(
      file.scene, file.calibration, thresholds, o.team, o.id, o.sensor, o.jitter, o.track);
  try {
    io::WriteFilesAtomic({{o.out, Csv(o.label, r)}});
  } catch (const InputError& e) {
    std::cerr << "patlab camtrack: " << e.what() << "\n";
    return kExitFailure;
  }
  if (o.quiet) return kExitOk;
  std::cerr << "camtrack " << o.label << ": " << r.frames << " complete frames, "
            << r.missed_patches << " missed patches, ";
  if (o.track.detect) {
    std::cerr << r.detected_frames << " detected, " << r.wrong_id_frames << " wrong ID, ";
  }
  std::cerr << FormatFixed(r.seconds, 2) << " s\n";
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("camtrack",
                        "the section-II track through the colour camera (per-colour patch std)",
                        RunCamtrack);

}  // namespace patlab::cli

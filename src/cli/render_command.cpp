// patlab render: a scene file (robots wearing a pattern at known poses, a ball, a camera) ->
// a synthetic camera frame (PNG) and its true poses (CSV), through render/scene_render.h.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/core/error.h"
#include "patlab/formats/scene_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/render/camera_render.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_io.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kRenderExamples = R"(examples:
  patlab render ssl-frame -o frame          # -> frame/frame.png, frame/truth.csv
  patlab render my-scene.toml -o f && patlab detect f/frame.png -t t.toml -c cal.toml -s det.toml
  patlab render ssl-frame --camera --frame 7 --uyvy -o cam   # -> cam/frame.uyvy
  patlab render ssl-frame --camera --read-noise-levels 0 \
      --shot-noise-gain 0 --roll-jitter-rad 0.001 --window 200,140,120,90 -o win

--camera renders through the colour camera (render/camera_render.h, docs/render.md): per-frame
camera jitter, exposure, RGGB sensor noise, bilinear demosaicing and YUV 4:2:2; frame F is the
same image in any run. Its frame is written as raw UYVY with --uyvy (what patlab detect
--raw-size reads), else as PNG (the UYVY frame converted to RGB).

A SCENE file names a pinhole calibration (its image_size_px is the frame size), a pattern and
its codebook, the RGB of every colour, the render options (blur, noise, seed), one [[robot]]
table per robot (team, id, x_mm, y_mm, theta_rad) and an optional [ball]; see docs/render.md.
The truth CSV has the columns team,id,x_mm,y_mm,theta_rad. Both files are written atomically.
Exit status: 0 ok, 1 cannot write the files, 2 bad input.
)";

struct RenderCommandOptions {
  std::string scene;
  std::string out;
  std::string truth;
  bool camera = false;
  uint64_t frame = 0;
  std::string window;  // X0,Y0,WIDTH,HEIGHT
  std::string sensor_seed = "1", jitter_seed = "1";
  bool no_bayer = false, chroma_444 = false, uyvy = false;
  render::CameraSensorOptions sensor;
  render::CameraJitter jitter;
};

void AddCameraOptions(po::options_description* d, RenderCommandOptions* o) {
  d->add_options()("camera", po::bool_switch(&o->camera),
                   "render through the colour camera (the options below)")(
      "frame", po::value(&o->frame), "frame identity (noise and jitter), default 0")(
      "exposure-gain", po::value(&o->sensor.exposure_gain),
      "linear gain on the scene colours, (0, 16], default 1")(
      "read-noise-levels", po::value(&o->sensor.read_noise_levels),
      "read noise per photosite, 8-bit levels, [0, 64], default 2")(
      "shot-noise-gain", po::value(&o->sensor.shot_noise_gain),
      "shot-noise variance per level of signal, [0, 4], default 0.05")(
      "no-bayer", po::bool_switch(&o->no_bayer), "a three-chip camera (no mosaic)")(
      "chroma-444", po::bool_switch(&o->chroma_444), "full-resolution colour instead of 4:2:2")(
      "sensor-seed", po::value(&o->sensor_seed), "sensor noise seed, default 1")(
      "roll-jitter-rad", po::value(&o->jitter.roll_sigma_rad),
      "std of the camera roll per frame, rad, [0, 0.1], default 0")(
      "height-jitter-mm", po::value(&o->jitter.height_sigma_mm),
      "std of the camera height change per frame, mm, [0, 1000], default 0")(
      "shift-jitter-mm", po::value(&o->jitter.shift_sigma_mm),
      "std of the camera shift along the floor per axis and frame, mm, [0, 1000], default 0")(
      "jitter-seed", po::value(&o->jitter_seed), "jitter seed, default 1")(
      "window", po::value(&o->window),
      "X0,Y0,WIDTH,HEIGHT: render only this part (X0, Y0, WIDTH even)");
}

// The camera frame the options ask for, as the file's bytes.
std::string RenderCamera(const RenderCommandOptions& o, const formats::SceneFile& file,
                         camera::Image* shown) {
  render::CameraSensorOptions sensor = o.sensor;
  sensor.bayer = !o.no_bayer;
  sensor.chroma_422 = !o.chroma_444;
  sensor.seed = ParseSeed(o.sensor_seed, "--sensor-seed");
  render::CameraJitter jitter = o.jitter;
  jitter.seed = ParseSeed(o.jitter_seed, "--jitter-seed");
  render::PixelWindow window{0, 0, file.scene.options.width_px, file.scene.options.height_px};
  if (!o.window.empty()) {
    const std::vector<int> w =
        ParseIntegerList(o.window, "--window", 0, 8192, "X0,Y0,WIDTH,HEIGHT in pixels");
    if (w.size() != 4) {
      throw InputError("--window has " + std::to_string(w.size()) +
                       " values; expected X0,Y0,WIDTH,HEIGHT in pixels");
    }
    window = {w[0], w[1], w[2], w[3]};
  }
  if (o.frame >= (uint64_t{1} << 32)) {
    throw InputError("--frame is " + std::to_string(o.frame) + "; expected an integer < 2^32");
  }
  *shown = render::RenderCameraWindow(file.scene, file.calibration.camera, sensor, o.frame, window,
                                      jitter);
  if (o.uyvy) {
    return {shown->data.begin(), shown->data.end()};
  }
  const std::vector<uint8_t> png = vision::EncodePng(camera::ToRgb(*shown));
  return {png.begin(), png.end()};
}

// The help's option groups (command_line.h).
const OptionGroups kRenderGroups = {
    {"camera",
     {"camera", "frame", "exposure-gain", "read-noise-levels", "shot-noise-gain", "no-bayer",
      "chroma-444", "sensor-seed", "window"}},
    {"camera jitter", {"roll-jitter-rad", "height-jitter-mm", "shift-jitter-mm", "jitter-seed"}},
    {"output", {"out", "uyvy"}}};

int RunRender(const std::vector<std::string>& args) {
  RenderCommandOptions o;
  po::options_description visible("usage: patlab render SCENE -o DIR [options]");
  visible.add_options()("help,h", "show this help")(
      "out,o", po::value(&o.out),
      "output directory: DIR/frame.png (or frame.uyvy) and DIR/truth.csv (required)")(
      "uyvy", po::bool_switch(&o.uyvy),
      "with --camera: write the raw UYVY frame DIR/frame.uyvy instead of frame.png");
  AddCameraOptions(&visible, &o);
  po::variables_map vm;
  if (!ParseArguments(args, visible, kRenderGroups, "scene", po::value(&o.scene), 1,
                      kRenderExamples, &vm,
                      {{"--truth", "-o DIR (DIR/truth.csv is always written)"}})) {
    return kExitOk;
  }
  if (o.scene.empty()) {
    throw InputError("missing SCENE; expected 'patlab render SCENE -o DIR'");
  }
  if (o.camera) ThrowCameraFlagProblem(o.sensor, o.jitter, vm);
  if (o.out.empty()) throw InputError("missing --out DIR; expected the directory to write to");
  if (o.uyvy && !o.camera) throw InputError("--uyvy without --camera; expected --camera with it");
  const std::filesystem::path dir(o.out);
  o.out = (dir / (o.uyvy ? "frame.uyvy" : "frame.png")).string();
  o.truth = (dir / "truth.csv").string();
  io::CheckWritable({o.out, o.truth});
  const formats::SceneFile file =
      formats::LoadSceneFile(FindData(o.scene, io::DataKind::kSettings));
  camera::Image frame;
  std::string bytes;
  if (o.camera) {
    bytes = RenderCamera(o, file, &frame);
  } else {
    if (vm.count("frame") + vm.count("window") + vm.count("exposure-gain") +
            vm.count("read-noise-levels") + vm.count("shot-noise-gain") + vm.count("sensor-seed") +
            vm.count("roll-jitter-rad") + vm.count("height-jitter-mm") +
            vm.count("shift-jitter-mm") + vm.count("jitter-seed") + (o.no_bayer ? 1 : 0) +
            (o.chroma_444 ? 1 : 0) >
        0) {
      throw InputError("camera options are given without --camera; expected --camera with them");
    }
    frame = render::RenderScene(file.scene, file.calibration.camera);
    const std::vector<uint8_t> png = vision::EncodePng(frame);
    bytes.assign(png.begin(), png.end());
  }
  const std::vector<std::pair<std::string, std::string>> files = {
      {o.out, bytes}, {o.truth, render::TruthCsv(file.scene)}};
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& e) {
    std::cerr << "patlab render: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << "wrote " << o.out << " (" << frame.width_px << "x" << frame.height_px << " px, "
            << file.scene.robots.size() << " robots" << (file.scene.ball_mm ? ", a ball" : "")
            << ") and " << o.truth << "\n";
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("render", "a synthetic camera frame of robots at known poses (PNG + truth)",
                        RunRender);

}  // namespace patlab::cli

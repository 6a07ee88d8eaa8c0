// patlab render: a scene file (robots wearing a pattern at known poses, a ball, a camera) ->
// a synthetic camera frame (PNG) and its true poses (CSV), through vision/scene_render.h.
#include <boost/program_options.hpp>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/scene_render.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab render tests/data/golden/ssl-frame.toml --out tests/data/golden/ssl-frame.png \
      --truth /tmp/ssl-frame.truth.csv
  patlab render my-scene.toml -o /tmp/frame.png && patlab detect /tmp/frame.png \
      --thresholds t.toml --calibration cal.toml --settings detector.toml

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
};

int RunRender(const std::vector<std::string>& args) {
  RenderCommandOptions o;
  po::options_description visible("usage: patlab render SCENE.toml --out FRAME.png [options]");
  visible.add_options()("help,h", "show this help")("out,o", po::value(&o.out),
                                                    "the rendered frame, PNG (required)")(
      "truth", po::value(&o.truth), "the true poses, CSV (team,id,x_mm,y_mm,theta_rad)");
  po::variables_map vm;
  if (!ParseArguments(args, visible, "scene", po::value(&o.scene), 1, kExamples, &vm)) {
    return kExitOk;
  }
  if (o.scene.empty()) {
    throw InputError("missing SCENE; expected 'patlab render SCENE.toml --out FRAME.png'");
  }
  if (o.out.empty()) throw InputError("missing --out FILE; expected the PNG file to write");

  io::CheckWritable(o.truth.empty() ? std::vector<std::string>{o.out}
                                    : std::vector<std::string>{o.out, o.truth});
  const vision::SceneFile file = vision::LoadSceneFile(o.scene);
  const vision::Image frame = vision::RenderScene(file.scene, file.calibration.camera);
  const std::vector<uint8_t> png = vision::EncodePng(frame);
  std::vector<std::pair<std::string, std::string>> files = {
      {o.out, std::string(png.begin(), png.end())}};
  if (!o.truth.empty()) files.emplace_back(o.truth, vision::TruthCsv(file.scene));
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& e) {
    std::cerr << "patlab render: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << "wrote " << o.out << " (" << frame.width_px << "x" << frame.height_px << " px, "
            << file.scene.robots.size() << " robots" << (file.scene.ball_mm ? ", a ball" : "")
            << ")" << (o.truth.empty() ? "" : " and " + o.truth) << "\n";
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("render", "a synthetic camera frame of robots at known poses (PNG + truth)",
                        RunRender);

}  // namespace patlab::cli

// Frames whose lines and robots do not fix a camera: patlab setup refuses them (exit 2 from the
// CLI) with the numbers rather than write a camera that maps the robots elsewhere. The scenes are
// fresh rendered seeds of scripts/setup_rendered.py (docs/setup.md), drawn without the colour
// camera's noise.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/render/scene_render.h"
#include "ssl_robot_scene.h"

namespace patlab::formats {
namespace {

// Fresh rendered seed 59: a camera 3.3 m up over ssl-div-a that sees one touch line and eight
// robots. The models with arc-shaped defence areas fitted a camera 0.42 m up to that single
// straight line, matching it to a short piece of arc and a line; setup wrote it, no robot decoded
// through it, and it exited 0. An arc whose pixels do not bend in the image now measures no
// curvature, the lines fix no camera, and setup refuses, saying so.
TEST(SetupCamera, OneStraightLineFixesNoCameraThoughItFitsAPieceOfArc) {
  const testing::TempDir dir;
  const SceneFile scene = SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 612.17
fy_px = 612.17
cx_px = 398.13
cy_px = 294.40
k1 = -0.0358
rotation_rodrigues = [3.099729, -0.043016, -0.116124]
translation_mm = [1363.8, -2163.4, 3312.6]
[heights]
default_mm = 140
)",
                                        "ssl-div-a", R"(field = [48, 114, 62]
body = [31, 30, 37]
blue = [36, 74, 227]
yellow = [244, 213, 49]
pink = [249, 94, 200]
green = [73, 213, 103]
orange = [255, 124, 27]
)",
                                        {{"blue", 2, -2772, -2082, 1.91},
                                         {"yellow", 11, -2788, -1418, -2.45},
                                         {"blue", 6, -1956, -1723, -1.94},
                                         {"yellow", 10, -2737, -3037, 1.79},
                                         {"blue", 4, -932, -1485, -2.75},
                                         {"yellow", 2, -1030, -3175, 2.86},
                                         {"blue", 1, -592, -3280, -3.01},
                                         {"yellow", 6, -2157, -3231, -2.18}});
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  const SetupOptions o = SslModels({"ssl-2008", "ssl-2009", "ssl-2014", "ssl-div-a"});
  try {
    const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
    ADD_FAILURE() << "accepted:\n" << SetupReportText(r);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("straight in the image"), std::string::npos) << e.what();
  }
}

// Fresh rendered seed 87: a camera 3.4 m up over ssl-2018's centre circle and halfway line, eight
// robots. Division A's and B's fields fit those lines 2.6 m apart (1976.4 and 1974.3 px of line)
// and the robots decode through both; setup kept the longer line and put every robot 2.6 m off (8
// false IDs). A tie of lines and robots between cameras that map the frame differently is refused.
TEST(SetupCamera, CamerasNeitherTheLinesNorTheRobotsDecideAreRefused) {
  const testing::TempDir dir;
  const SceneFile scene = SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 605.37
fy_px = 605.37
cx_px = 383.31
cy_px = 290.22
k1 = -0.0428
rotation_rodrigues = [-0.433622, -3.055944, 0.008526]
translation_mm = [154.1, 541.2, 3375.0]
[heights]
default_mm = 140
)",
                                        "ssl-2018", R"(field = [39, 104, 51]
body = [29, 30, 33]
blue = [33, 75, 206]
yellow = [224, 216, 44]
pink = [228, 96, 182]
green = [67, 216, 93]
orange = [238, 126, 25]
)",
                                        {{"blue", 7, 1151, -1999, 2.41},
                                         {"yellow", 13, -660, -234, -1.58},
                                         {"blue", 0, 1370, -1233, -2.87},
                                         {"yellow", 7, 1102, -273, -1.14},
                                         {"blue", 14, -114, -36, 2.87},
                                         {"yellow", 5, 215, -1695, -3.11},
                                         {"blue", 8, -1026, 58, -3.03},
                                         {"yellow", 11, 986, -718, -2.69}});
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  const SetupOptions o = SslModels({"ssl-div-a", "ssl-div-b"});
  try {
    const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
    ADD_FAILURE() << "accepted:\n" << SetupReportText(r);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("neither the lines nor the robots decide the camera"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace patlab::formats

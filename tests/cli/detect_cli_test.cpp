// patlab detect end to end: frames written by the test (rendered discs), the binary run as a
// user would, its stdout, stderr and exit status checked.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "patlab/detect/codebook.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {
namespace {

struct CliRun {
  int status;
  std::string out, err;
};

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() / "patlab_detect_cli" / info->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

CliRun RunPatlab(const std::string& dir, const std::string& args) {
  const std::string cmd =
      std::string(PATLAB_BINARY) + " " + args + " >" + dir + "/out.txt 2>" + dir + "/err.txt";
  const int raw = std::system(cmd.c_str());
  return {WEXITSTATUS(raw), Slurp(dir + "/out.txt"), Slurp(dir + "/err.txt")};
}

CliRun Detect(const std::string& dir, const std::string& args) {
  return RunPatlab(dir, "detect " + args);
}

// One blue disc of radius 10 px at (30.5, 20.25) on grey; calibration 2 mm per px, y up.
void WriteScene(const std::string& dir) {
  const std::vector<render::Disc> discs = {{Vec2(30.5, 20.25), 10, {20, 40, 230}}};
  WritePng(render::RenderDiscs(64, 48, {90, 90, 90}, discs, 8), dir + "/a.png");
  std::ofstream(dir + "/t.toml") << "[[class]]\nname = \"blue\"\nu = [160, 255]\nv = [0, 120]\n";
  std::ofstream(dir + "/c.toml") << "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
                                    "matrix = [[2, 0, 0], [0, -2, 96], [0, 0, 1]]\n";
}

TEST(DetectCli, WritesCalibratedBlobsWithoutSettings) {
  const std::string dir = Dir();
  WriteScene(dir);
  const CliRun r = Detect(dir, dir + "/a.png -t " + dir + "/t.toml -c " + dir + "/c.toml");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  EXPECT_EQ(header, "frame,colour,x_mm,y_mm,area_mm2,x_px,y_px,area_px");
  // x = 2 u = 61 mm, y = 96 - 2 v = 55.5 mm, up to digitisation (0.15 px = 0.3 mm).
  double x, y;
  ASSERT_EQ(std::sscanf(row.substr(row.find(",blue,") + 6).c_str(), "%lf,%lf", &x, &y), 2) << row;
  EXPECT_NEAR(x, 61.0, 0.3);
  EXPECT_NEAR(y, 55.5, 0.3);
}

TEST(DetectCli, TruncatedFrameIsExitTwoWithNoOutput) {
  const std::string dir = Dir();
  WriteScene(dir);
  std::vector<uint8_t> bytes = ReadFileBytes(dir + "/a.png");
  bytes.resize(40);
  std::ofstream(dir + "/b.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), 40);
  const std::string args =
      dir + "/a.png " + dir + "/b.png -t " + dir + "/t.toml -c " + dir + "/c.toml";
  CliRun r = Detect(dir, args);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("patlab detect: " + dir + "/b.png: byte 40: truncated PNG"),
            std::string::npos)
      << r.err;
  // --keep-going: the good frame is written, the bad one reported, and the status says so.
  r = Detect(dir, args + " --keep-going");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("a.png,blue,"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("(skipped: --keep-going)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("patlab detect: 1 of 2 frame(s) failed"), std::string::npos) << r.err;
}

TEST(DetectCli, BadThresholdsFileNamesFileAndLine) {
  const std::string dir = Dir();
  WriteScene(dir);
  std::ofstream(dir + "/colors.txt")
      << "[Colors]\n(0,0,255) 0.5 1 blue\n[Thresholds]\n(0:255, 160:255)\n";
  const CliRun r = Detect(dir, dir + "/a.png -t " + dir + "/colors.txt -c " + dir + "/c.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "patlab detect: " + dir +
                       "/colors.txt:4: bad [Thresholds] line '(0:255, 160:255)'; "
                       "expected (Ylo:Yhi, Ulo:Uhi, Vlo:Vhi)\n");
  EXPECT_EQ(r.out, "");
}

TEST(DetectCli, RawFrameOfTheWrongSize) {
  const std::string dir = Dir();
  WriteScene(dir);
  std::ofstream(dir + "/f.yuv", std::ios::binary) << std::string(100, '\x80');
  const CliRun r =
      Detect(dir, dir + "/f.yuv --raw-size 64x48 -t " + dir + "/t.toml -c " + dir + "/c.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "patlab detect: " + dir +
                       "/f.yuv: 100 bytes; expected 6144 bytes for a 64x48 UYVY "
                       "frame (width x height x 2)\n");
}

// --timing: one table from the stage profiles -- the frame's stages named as vision/pipeline.h
// numbers them, then under "6 detect" the detector's own stages named as detect/detector.h numbers
// them -- each with its time per frame (and its counters); without --timing, none of it.
TEST(DetectCli, TimingShowsTheDetectorStagesUnderStageSix) {
  const std::string dir = Dir();
  WriteScene(dir);
  const std::string args = dir + "/a.png -t " + dir + "/t.toml -c " + dir + "/c.toml -s " +
                           PATLAB_SOURCE_DIR + "/experiments/detector.toml";
  const CliRun timed = Detect(dir, args + " --timing");
  ASSERT_EQ(timed.status, 0) << timed.err;
  // Stage lines in this order, each with a time per frame.
  const std::vector<std::string> stages = {
      "  1 read           ",     "  2 colour lookup  ",     "  3 runs           ",
      "  4 regions        ",     "  5 blobs to mm    ",     "  6 detect         ",
      "      1 candidates     ", "      2 neighbours     ", "      3 radial sort    ",
      "      4 fit rotations  ", "      5 identify       ", "      6 missing patch  ",
      "      7 conflicts      ", "      8 pose           ", "  total            "};
  const std::regex time_per_frame(" *[0-9]+\\.[0-9]{4} ms");
  size_t at = 0;
  for (const std::string& stage : stages) {
    const size_t found = timed.err.find("\n" + stage, at);
    ASSERT_NE(found, std::string::npos) << "no '" << stage << "' after offset " << at << " in\n"
                                        << timed.err;
    at = found + 1;
    const std::string rest =
        timed.err.substr(at + stage.size(), timed.err.find('\n', at) - at - stage.size());
    EXPECT_TRUE(std::regex_search(rest, time_per_frame, std::regex_constants::match_continuous))
        << stage << rest;
  }
  // The detector's stages are numbered 1..8 under stage 6, not "6.1 ...": no line starts with a
  // sub-number (a time such as "6.1663 ms" is not a stage).
  EXPECT_FALSE(std::regex_search(timed.err, std::regex("\n *6\\.[0-9]+ +[a-z]"))) << timed.err;
  const CliRun plain = Detect(dir, args);
  ASSERT_EQ(plain.status, 0) << plain.err;
  // Without --timing no table; what stderr holds are the warnings that the scene's thresholds
  // have no class for the palette colours yellow, pink and green experiments/detector.toml's
  // patterns use (docs/detect.md).
  EXPECT_EQ(plain.err.find("per frame"), std::string::npos) << plain.err;
  EXPECT_EQ(std::count(plain.err.begin(), plain.err.end(), '\n'), 3) << plain.err;
  EXPECT_NE(plain.err.find("patlab detect: warning: detector colour \"pink\" is used by a "
                           "pattern but no class of "),
            std::string::npos);
}

// --debug DIR: the library's numbered per-stage images of each frame.
TEST(DetectCli, DebugWritesTheNumberedStageImages) {
  const std::string dir = Dir();
  WriteScene(dir);
  const CliRun r =
      Detect(dir, dir + "/a.png -t " + dir + "/t.toml -c " + dir + "/c.toml -s " +
                      PATLAB_SOURCE_DIR + "/experiments/detector.toml --debug " + dir + "/debug");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name :
       {"a.2_colour_lookup.png", "a.4_regions.png", "a.5_blobs_to_mm.png", "a.6_detect.png"}) {
    EXPECT_EQ(ReadFrame(dir + "/debug/" + name).width_px, 64) << name;
  }
}

TEST(DetectCli, DetectsTheSharedStandardPatternSheet) {
  const std::string frames = std::string(PATLAB_SOURCE_DIR) + "/../shared/frames";
  if (!std::filesystem::exists(frames)) GTEST_SKIP() << "no shared frames at " << frames;
  const std::string dir = Dir();
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision";
  const CliRun r = Detect(dir, frames + "/ssl-standard-pattern-2010-16ids.png -t " + data +
                                   "/ssl-standard-sheet.thresholds.toml -c " + data +
                                   "/ssl-standard-sheet.calibration.toml -s " + PATLAB_SOURCE_DIR +
                                   "/experiments/detector.toml --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  // 16 robots, IDs 0..15 in row-major cells of 200 mm, all facing +x (up the sheet).
  for (int id = 0; id < 16; ++id) {
    EXPECT_NE(r.out.find("\"id\": " + std::to_string(id) + ","), std::string::npos) << id;
  }
  EXPECT_EQ(r.out.find("\"id\": 16,"), std::string::npos);
}

// The segmentation's edge loss: a settings file's [frame] edge_loss_px, and --edge-loss-px over
// it. One blue ssl-standard robot (ID 0) at 2 mm per px whose 20 mm dots are drawn with radius
// 11 mm: area ratio (11/20)^2 = 0.30, below area_ratio_min 0.4 of the full dot but above 0.4 times
// the dot shrunk by a 2 px (4 mm) rim, 0.4 (16/20)^2 = 0.256.
TEST(DetectCli, EdgeLossFromTheSettingsAndTheFlag) {
  const std::string dir = Dir();
  const std::string shipped = std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml";
  const detect::DetectorConfig config = formats::LoadDetectorSettings(shipped);
  const detect::DetectorPattern& dp = config.patterns[0];
  const std::vector<int> slots = detect::IdSlots(dp.pattern);
  std::vector<render::Disc> discs;
  for (int i = 0; i < dp.pattern.size(); ++i) {
    const Patch& patch = dp.pattern.patches[i];
    if (patch.role != PatchRole::kId) {
      discs.push_back({patch.position_mm, patch.radius_mm, {20, 40, 230}});
      continue;
    }
    const int slot = static_cast<int>(std::find(slots.begin(), slots.end(), i) - slots.begin());
    const std::string& colour = dp.codebook.colours[dp.codebook.entries[0].colour[slot]];
    discs.push_back({patch.position_mm, 11.0,
                     colour == "pink" ? render::Rgb{250, 60, 220} : render::Rgb{40, 230, 60}});
  }
  const std::string calibration =
      "model = \"homography\"\nimage_size_px = [200, 150]\n[[homography]]\nheight_mm = 0\n"
      "matrix = [[2, 0, -200], [0, -2, 150], [0, 0, 1]]\n";
  std::ofstream(dir + "/c.toml") << calibration;
  WritePng(
      render::RenderWorldDiscs(200, 150, formats::ParseCalibration(calibration, "c.toml").camera,
                               0.0, {70, 70, 70}, discs),
      dir + "/robot.png");
  std::ofstream(dir + "/t.toml")
      << "space = \"rgb\"\n"
         "[[class]]\nname = \"blue\"\nr = [0, 80]\ng = [0, 100]\nb = [180, 255]\n"
         "[[class]]\nname = \"pink\"\nr = [200, 255]\ng = [0, 110]\nb = [160, 255]\n"
         "[[class]]\nname = \"green\"\nr = [0, 90]\ng = [180, 255]\nb = [0, 110]\n";
  std::ofstream(dir + "/s.toml") << "palette = [\"blue\", \"yellow\", \"pink\", \"green\"]\n"
                                    "[frame]\nedge_loss_px = 2\n[[pattern]]\npattern = \""
                                 << PATLAB_SOURCE_DIR
                                 << "/patterns/ssl-standard.toml\"\ncodebook = \""
                                 << PATLAB_SOURCE_DIR
                                 << "/patterns/ssl-standard.codebook.toml\"\n"
                                    "key_colours = [\"blue\"]\n";
  const std::string args =
      dir + "/robot.png -t " + dir + "/t.toml -c " + dir + "/c.toml -s " + dir + "/s.toml";
  const CliRun file_only = Detect(dir, args);  // the file's 2 px
  ASSERT_EQ(file_only.status, 0) << file_only.err;
  EXPECT_NE(file_only.out.find(",blue,0,ok,"), std::string::npos) << file_only.out;
  EXPECT_EQ(std::count(file_only.out.begin(), file_only.out.end(), '\n'), 2) << file_only.out;
  for (const char* px : {"0", "1"}) {  // the flag over the file
    const CliRun flag = Detect(dir, args + " --edge-loss-px " + px);
    ASSERT_EQ(flag.status, 0) << flag.err;
    EXPECT_EQ(std::count(flag.out.begin(), flag.out.end(), '\n'), 1) << px << "\n" << flag.out;
  }
}

// Settings that travel (docs/detect.md): every shared frame with the shipped detector numbers --
// the [detector] and [frame] tables of experiments/detector.toml -- and only what the robots
// wear from the frame's own settings (palette, patterns, ID colours); the SSL 2008 frame through
// the calibration patlab calibrate fits to its points. Every detection must be a robot of the
// frame (its key within 60 mm of where the calibration puts a robot's centre pixel, read off the
// frame by eye, docs/paper-reproduction.md), no robot twice, with the ID its sector colours show.
struct SharedFrameRun {
  std::vector<detect::Detection> detections;
  camera::Calibration calibration;
};

SharedFrameRun DetectWithShippedSettings(const std::string& frame, const std::string& thresholds,
                                         const std::string& calibration,
                                         const std::string& settings,
                                         const std::string& pattern_file = "") {
  const std::string shipped = std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml";
  detect::DetectorConfig config = formats::LoadDetectorSettings(settings);
  config.options = formats::LoadDetectorSettings(shipped).options;
  if (!pattern_file.empty()) {
    const detect::DetectorPattern& p = config.patterns[0];
    config.patterns[0] = formats::MakeDetectorPattern(formats::LoadPatternFile(pattern_file),
                                                      p.key_colours, "", p.codebook.colours);
  }
  FrameDetectorOptions options;
  ApplyFrameSettings(formats::LoadFrameSettings(shipped), &options);
  FrameDetector frames(formats::LoadThresholds(thresholds), formats::LoadCalibration(calibration),
                       config, options);
  return {frames.DetectFile(frame).detections, formats::LoadCalibration(calibration)};
}

struct Robot {
  double u_px, v_px;
  std::string team;
  int id;  // -1: not known from the frame
};

// Each detection matches one robot (nearest within 60 mm, team and ID as given); returns the
// matched robots' indices.
std::vector<int> MatchRobots(const SharedFrameRun& run, const std::vector<Robot>& robots,
                             const std::vector<std::string>& palette) {
  std::vector<int> matched;
  for (const detect::Detection& d : run.detections) {
    int best = -1;
    double best_mm = 60.0;
    for (size_t i = 0; i < robots.size(); ++i) {
      const auto world = run.calibration.camera.PixelToWorld(Vec2(robots[i].u_px, robots[i].v_px),
                                                             run.calibration.default_height_mm);
      if (!world) continue;
      const double mm = std::hypot(world->x() - d.pose.x_mm, world->y() - d.pose.y_mm);
      if (mm < best_mm) best = static_cast<int>(i), best_mm = mm;
    }
    EXPECT_GE(best, 0) << "a detection at (" << d.pose.x_mm << ", " << d.pose.y_mm
                       << ") mm is no robot of the frame";
    if (best < 0) continue;
    EXPECT_EQ(palette[d.team_colour], robots[best].team) << best;
    EXPECT_EQ(d.id, robots[best].id) << best;
    EXPECT_EQ(std::count(matched.begin(), matched.end(), best), 0) << best;
    matched.push_back(best);
  }
  std::sort(matched.begin(), matched.end());
  return matched;
}

TEST(DetectCli, ShippedSettingsTravelToEverySharedFrame) {
  const std::string frames = std::string(PATLAB_SOURCE_DIR) + "/../shared/frames";
  if (!std::filesystem::exists(frames)) GTEST_SKIP() << "no shared frames at " << frames;
  const std::string dir = Dir();
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  const std::string palette_of_sheet =
      std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml";

  // The sheet: 16 blue robots, IDs 0..15 in row-major cells of 200 mm (1 px = 1 mm).
  const SharedFrameRun sheet = DetectWithShippedSettings(
      frames + "/ssl-standard-pattern-2010-16ids.png", data + "ssl-standard-sheet.thresholds.toml",
      data + "ssl-standard-sheet.calibration.toml", palette_of_sheet);
  std::vector<Robot> cells;
  for (int id = 0; id < 16; ++id) {
    const auto centre = sheet.calibration.camera.WorldToPixel(
        Vec2(711.0 - 200.0 * (id / 4), 700.0 - 200.0 * (id % 4)),
        sheet.calibration.default_height_mm);
    ASSERT_TRUE(centre.has_value());
    cells.push_back({centre->x(), centre->y(), "blue", id});
  }
  EXPECT_EQ(
      MatchRobots(sheet, cells, formats::LoadDetectorSettings(palette_of_sheet).palette).size(),
      16u);

  // SSL 2008 through the fitted calibration: the yellow robot (557, 200) with all sectors, the two
  // blue robots without their black sector (merged with the body), IDs 6 and 15 as their sector
  // colours read (pink/white/pink, green/white/pink), and the yellow robot (343, 58) without its
  // grey green sector (ID unknown). The yellow robot (258, 82) and the one held in a hand at
  // (40, 445) stay missed (docs/detect.md explains why).
  const CliRun fit = RunPatlab(
      dir, "calibrate " + data + "ssl-2008.calibration-input.toml --out " + dir + "/fitted");
  ASSERT_EQ(fit.status, 0) << fit.err;
  const SharedFrameRun ssl =
      DetectWithShippedSettings(frames + "/ssl-field-2008.jpg", data + "ssl-2008.thresholds.toml",
                                dir + "/fitted/calibration.toml", data + "ssl-2008.detector.toml",
                                data + "patterns/kiks-sectors-fitted.toml");
  const std::vector<Robot> ssl_robots = {{557, 200, "yellow", 5}, {258, 82, "yellow", -1},
                                         {343, 58, "yellow", -1}, {434, 559, "blue", 6},
                                         {478, 564, "blue", 15},  {40, 445, "", -1}};
  const std::vector<std::string> ssl_palette =
      formats::LoadDetectorSettings(data + "ssl-2008.detector.toml").palette;
  EXPECT_EQ(MatchRobots(ssl, ssl_robots, ssl_palette), (std::vector<int>{0, 2, 3, 4}));
  int fitted_on_fewer = 0;
  for (const detect::Detection& d : ssl.detections) {
    fitted_on_fewer += d.status == detect::DetectionStatus::kMissingPatch ? 1 : 0;
  }
  EXPECT_EQ(fitted_on_fewer, 3);

  // VSS: 5 robots of two designs (vss.detector.toml's patterns), each found with its ID at the
  // place tests/vision/real_frames_test.cpp checks with the frame's own settings.
  const SharedFrameRun vss =
      DetectWithShippedSettings(frames + "/vss-test-frame.png", data + "vss.colors.txt",
                                data + "vss.calibration.toml", data + "vss.detector.toml");
  std::vector<Robot> vss_robots;
  for (const auto& [x, y, team, id] : std::vector<std::tuple<double, double, std::string, int>>{
           {375.64, -634.29, "light-green", 2},
           {-470.30, 597.65, "blue", 1},
           {-489.50, -231.36, "light-green", 0},
           {-186.23, -206.61, "light-green", 1},
           {-327.28, -393.77, "light-green", 2}}) {
    const auto centre =
        vss.calibration.camera.WorldToPixel(Vec2(x, y), vss.calibration.default_height_mm);
    ASSERT_TRUE(centre.has_value());
    vss_robots.push_back({centre->x(), centre->y(), team, id});
  }
  EXPECT_EQ(MatchRobots(vss, vss_robots,
                        formats::LoadDetectorSettings(data + "vss.detector.toml").palette)
                .size(),
            5u);
}

}  // namespace
}  // namespace patlab::vision

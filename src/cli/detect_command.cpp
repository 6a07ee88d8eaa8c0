// patlab detect: real frames -> (stage 1) read -> (2-4) CMVision regions -> (5) blobs in mm on
// the pattern planes -> (6) the shared detector (detect/) -> detections as CSV or JSON.
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "patlab/core/error.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/toml_util.h"
#include "patlab/vision/debug_image.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/pipeline.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;

constexpr const char* kExamples = R"(examples:
  patlab detect frames/ --thresholds tests/data/vision/ssl-2008.thresholds.toml \
      --calibration tests/data/vision/ssl-2008.calibration.toml \
      --settings tests/data/vision/ssl-2008.detector.toml --debug /tmp/debug
  patlab detect cam.yuv --raw-size 780x580 --thresholds colors.txt --calibration cal.toml --blobs
  patlab detect list.txt --thresholds t.toml --calibration cal.toml --format json --out det.json --timing

FRAME arguments: PNG, JPEG or binary PPM files; raw UYVY files (.yuv .uyvy .raw, with --raw-size);
directories (their frames, sorted by name); or a .txt/.list file naming one frame per line.
Without --settings (no patterns to detect) the calibrated blobs are written instead of detections.
Output is written only when every frame succeeded; with --keep-going a bad frame is reported on
stderr, skipped, and the exit status is 2 after the rest is written.
Exit status: 0 ok, 1 cannot write results, 2 bad input.
)";

struct DetectOptions {
  std::vector<std::string> frames;
  std::string thresholds;
  std::string calibration;
  std::string settings;
  std::string raw_size;
  std::string format = "csv";
  std::string out;
  std::string debug_dir;
  bool blobs = false;
  bool timing = false;
  bool keep_going = false;
  vision::SegmenterOptions segmenter;
};

struct StageTotals {
  double read_ms = 0, detect_ms = 0;
  vision::VisionStats vision;
  detect::DetectStats detect;
  int frames = 0;
};

std::string Fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

void ParseRawSize(const std::string& text, int* width, int* height) {
  const size_t x = text.find('x');
  try {
    size_t used_w = 0, used_h = 0;
    if (x != std::string::npos) {
      *width = std::stoi(text.substr(0, x), &used_w);
      *height = std::stoi(text.substr(x + 1), &used_h);
      if (used_w == x && used_h == text.size() - x - 1 && *width > 0 && *height > 0) return;
    }
  } catch (const std::exception&) {
  }
  throw InputError("--raw-size is '" + text + "'; expected WIDTHxHEIGHT, e.g. 780x580");
}

bool IsRaw(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".yuv" || ext == ".uyvy" || ext == ".raw";
}

}  // namespace

int RunDetect(const std::vector<std::string>& args) {
  DetectOptions o;
  po::options_description visible(
      "patlab detect FRAME... --thresholds FILE --calibration FILE [options]");
  visible.add_options()("help,h", "show this help")(
      "thresholds,t", po::value(&o.thresholds),
      "colour thresholds: CMVision colors.txt or our TOML form (required)")(
      "calibration,c", po::value(&o.calibration),
      "camera calibration TOML: pinhole or homography, plane heights (required)")(
      "settings,s", po::value(&o.settings),
      "detector settings TOML (palette, patterns, options; e.g. experiments/detector.toml)")(
      "raw-size", po::value(&o.raw_size), "WIDTHxHEIGHT of raw UYVY frames (.yuv .uyvy .raw)")(
      "format", po::value(&o.format), "csv (default) or json")(
      "out,o", po::value(&o.out), "output file, written atomically (default: stdout)")(
      "blobs", po::bool_switch(&o.blobs), "write the calibrated blobs instead of detections")(
      "debug", po::value(&o.debug_dir), "write an annotated PNG per frame into this directory")(
      "timing", po::bool_switch(&o.timing), "per-stage timing and counters on stderr")(
      "keep-going", po::bool_switch(&o.keep_going), "report a bad frame and go on with the rest")(
      "min-area-px", po::value(&o.segmenter.min_area_px),
      "drop regions with fewer pixels (default 4)")(
      "min-fill", po::value(&o.segmenter.min_fill),
      "drop regions filling less of their bounding box (default 0)");
  po::variables_map vm;
  if (!ParseArguments(args, visible, "frame", po::value(&o.frames), -1, kExamples, &vm)) {
    return kExitOk;
  }
  if (o.frames.empty())
    throw InputError("no frames; expected 'patlab detect FRAME...' (see --help)");
  if (o.thresholds.empty())
    throw InputError("missing --thresholds FILE; expected a colors.txt or thresholds TOML file");
  if (o.calibration.empty())
    throw InputError("missing --calibration FILE; expected a calibration TOML file");
  if (o.format != "csv" && o.format != "json") {
    throw InputError("--format is '" + o.format + "'; expected csv or json");
  }
  int raw_width = 0, raw_height = 0;
  if (!o.raw_size.empty()) ParseRawSize(o.raw_size, &raw_width, &raw_height);
  vision::Validate(o.segmenter);

  vision::VisionPipeline pipeline(vision::LoadThresholds(o.thresholds),
                                  vision::LoadCalibration(o.calibration), o.segmenter);
  const vision::Thresholds& thresholds = pipeline.thresholds();
  std::optional<detect::Detector> detector;
  std::vector<int> palette_label;  // class index -> detector palette label (-1: not used)
  if (!o.settings.empty()) {
    detector.emplace(detect::LoadDetectorSettings(o.settings));
    for (const vision::ColorClass& c : thresholds.classes)
      palette_label.push_back(detector->ColourLabel(c.name));
  }
  const bool write_blobs = o.blobs || !detector;
  const std::vector<std::string> frames = vision::ExpandFrameList(o.frames);

  std::ostringstream csv;
  nlohmann::json json = nlohmann::json::array();
  if (write_blobs) {
    csv << "frame,colour,x_mm,y_mm,area_mm2,x_px,y_px,area_px\n";
  } else {
    csv << "frame,pattern,team,id,status,x_mm,y_mm,theta_rad,residual_mm2,confidence\n";
  }
  std::vector<std::pair<std::string, std::string>> debug_files;
  StageTotals totals;
  int failed = 0;
  std::vector<detect::Blob> blobs, palette_blobs;
  std::vector<int> blob_of_palette_blob;
  std::vector<detect::Detection> detections;
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string& path = frames[f];
    const std::string frame_name = fs::path(path).filename().string();
    try {
      // Stage 1: read.
      auto t = std::chrono::steady_clock::now();
      const vision::Image image = IsRaw(path) && raw_width > 0
                                      ? vision::ReadRawUyvy(path, raw_width, raw_height)
                                      : vision::ReadFrame(path);
      totals.read_ms +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
      pipeline.CheckFrameSize(image, path);
      // Stages 2-5.
      vision::VisionStats vstats;
      pipeline.Process(image, &blobs, &vstats);
      totals.vision += vstats;
      ++totals.frames;
      const auto& regions = pipeline.segmenter().regions();
      nlohmann::json frame_json = {{"frame", path}};
      if (write_blobs) {
        nlohmann::json list = nlohmann::json::array();
        for (size_t i = 0; i < blobs.size(); ++i) {
          const vision::Region& r = regions[static_cast<size_t>(pipeline.blob_region()[i])];
          const std::string& colour = thresholds.classes[static_cast<size_t>(blobs[i].colour)].name;
          csv << path << "," << colour << "," << Fixed(blobs[i].position_mm.x(), 2) << ","
              << Fixed(blobs[i].position_mm.y(), 2) << "," << Fixed(blobs[i].area_mm2, 1) << ","
              << Fixed(r.centroid_px.x(), 3) << "," << Fixed(r.centroid_px.y(), 3) << ","
              << r.area_px << "\n";
          list.push_back({{"colour", colour},
                          {"x_mm", blobs[i].position_mm.x()},
                          {"y_mm", blobs[i].position_mm.y()},
                          {"area_mm2", blobs[i].area_mm2},
                          {"x_px", r.centroid_px.x()},
                          {"y_px", r.centroid_px.y()},
                          {"area_px", r.area_px}});
        }
        frame_json["blobs"] = list;
      }
      // Stage 6: detect, on the blobs whose class is in the detector's palette.
      detections.clear();
      if (detector) {
        palette_blobs.clear();
        blob_of_palette_blob.clear();
        for (size_t i = 0; i < blobs.size(); ++i) {
          const int label = palette_label[static_cast<size_t>(blobs[i].colour)];
          if (label < 0) continue;
          palette_blobs.push_back(detect::Blob{blobs[i].position_mm, label, blobs[i].area_mm2});
          blob_of_palette_blob.push_back(static_cast<int>(i));
        }
        t = std::chrono::steady_clock::now();
        detect::DetectStats dstats;
        dstats.collect_timing = o.timing;
        detector->Detect(palette_blobs, &detections, &dstats);
        totals.detect_ms +=
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
        totals.detect += dstats;
      }
      if (!write_blobs) {
        const auto& config = detector->config();
        nlohmann::json list = nlohmann::json::array();
        for (const detect::Detection& d : detections) {
          const std::string& pattern = config.patterns[static_cast<size_t>(d.pattern)].pattern.name;
          const std::string team =
              d.team_colour >= 0 ? config.palette[static_cast<size_t>(d.team_colour)] : "";
          const std::string status(detect::DetectionStatusName(d.status));
          csv << path << "," << pattern << "," << team << "," << d.id << "," << status << ","
              << Fixed(d.pose.x_mm, 2) << "," << Fixed(d.pose.y_mm, 2) << ","
              << Fixed(d.pose.theta_rad, 4) << "," << Fixed(d.residual_mm2, 2) << ","
              << Fixed(d.confidence, 4) << "\n";
          list.push_back({{"pattern", pattern},
                          {"team", team},
                          {"id", d.id},
                          {"status", status},
                          {"x_mm", d.pose.x_mm},
                          {"y_mm", d.pose.y_mm},
                          {"theta_rad", d.pose.theta_rad},
                          {"residual_mm2", d.residual_mm2},
                          {"confidence", d.confidence}});
        }
        frame_json["detections"] = list;
      }
      json.push_back(frame_json);
      if (!o.debug_dir.empty()) {
        vision::Image debug = vision::DrawRegions(image, pipeline.segmenter(), thresholds);
        for (const detect::Detection& d : detections) {
          // Draw at the key blob's plane height; the heading is the model x axis, 100 mm long.
          const int key = d.blob[static_cast<size_t>(
              detector->config().patterns[static_cast<size_t>(d.pattern)].pattern.key_index)];
          const double height =
              key >= 0
                  ? pipeline.class_height_mm(
                        blobs[static_cast<size_t>(blob_of_palette_blob[static_cast<size_t>(key)])]
                            .colour)
                  : pipeline.calibration().default_height_mm;
          const auto& camera = pipeline.calibration().camera;
          const auto centre = camera.WorldToPixel(Vec2(d.pose.x_mm, d.pose.y_mm), height);
          const auto tip = camera.WorldToPixel(d.pose.Apply(Vec2(100, 0)), height);
          const auto rim = camera.WorldToPixel(d.pose.Apply(Vec2(0, 90)), height);
          if (!centre || !tip || !rim) continue;
          const std::string label = d.id >= 0 ? std::to_string(d.id) : "?";
          DrawDetection(&debug, *centre, (*rim - *centre).norm(), *tip, label, {255, 255, 255});
        }
        debug_files.emplace_back(
            (fs::path(o.debug_dir) / (fs::path(path).stem().string() + ".png")).string(), [&] {
              const auto bytes = vision::EncodePng(debug);
              return std::string(bytes.begin(), bytes.end());
            }());
      }
    } catch (const InputError& e) {
      if (!o.keep_going) throw;
      ++failed;
      std::cerr << "patlab detect: " << e.what() << " (skipped: --keep-going)\n";
    }
  }

  std::string output = o.format == "csv" ? csv.str() : json.dump(2) + "\n";
  try {
    if (!o.out.empty()) debug_files.emplace_back(o.out, output);
    if (!debug_files.empty()) {
      if (!o.debug_dir.empty()) fs::create_directories(o.debug_dir);
      io::WriteFilesAtomic(debug_files);
    }
  } catch (const std::exception& e) {
    std::cerr << "patlab detect: " << e.what() << "\n";
    return kExitFailure;
  }
  if (o.out.empty()) std::cout << output;
  if (o.timing && totals.frames > 0) {
    const double n = totals.frames;
    const auto& v = totals.vision;
    std::cerr << "patlab detect: " << totals.frames << " frame(s), per frame:\n"
              << "  1 read      " << Fixed(totals.read_ms / n, 3) << " ms\n"
              << "  2 classify  " << Fixed(v.classify_ms / n, 3) << " ms\n"
              << "  3 encode    " << Fixed(v.encode_ms / n, 3) << " ms  runs "
              << Fixed(v.runs / n, 0) << "\n"
              << "  4 regions   " << Fixed(v.regions_ms / n, 3) << " ms  regions "
              << Fixed(v.raw_regions / n, 0) << " -> kept " << Fixed(v.regions / n, 0) << "\n"
              << "  5 camera    " << Fixed(v.camera_ms / n, 3) << " ms  blobs "
              << Fixed(v.blobs / n, 0) << " (off plane " << Fixed(v.off_plane / n, 0) << ")\n";
    if (detector) {
      std::cerr << "  6 detect    " << Fixed(totals.detect_ms / n, 3) << " ms  key candidates "
                << Fixed(totals.detect.key_candidates / n, 1) << ", detections "
                << Fixed(totals.detect.detections / n, 1) << "\n";
      // The detector's own stages (detect::DetectStageTimes), indented under stage 6.
      const detect::DetectStats& d = totals.detect;
      auto ms = [n](long ns) { return Fixed(static_cast<double>(ns) * 1e-6 / n, 4) + " ms"; };
      std::cerr << "      6.1 key candidates   " << ms(d.time.key_candidates_ns) << "  candidates "
                << Fixed(d.key_candidates / n, 1) << "\n"
                << "      6.2 neighbours       " << ms(d.time.neighbours_ns) << "  found "
                << Fixed(d.neighbours / n, 1) << " (cut " << Fixed(d.neighbours_cut / n, 1) << ")\n"
                << "      6.3 radial sort      " << ms(d.time.radial_sort_ns) << "\n"
                << "      6.4 correspondences  " << ms(d.time.correspondences_ns) << "  rotations "
                << Fixed(d.correspondences / n, 1) << ", geometry passed "
                << Fixed(d.geometry_passed / n, 1) << "\n"
                << "      6.5 colours / ID     " << ms(d.time.colours_ns) << "  colour rejected "
                << Fixed(d.colour_rejected / n, 1) << ", ambiguous " << Fixed(d.ambiguous / n, 1)
                << ", missing patch " << Fixed(d.missing_fits / n, 1) << "\n"
                << "      6.6 conflicts        " << ms(d.time.conflicts_ns) << "  dropped "
                << Fixed(d.conflicts / n, 1) << "\n"
                << "      6.7 pose             " << ms(d.time.pose_ns) << "  detections "
                << Fixed(d.detections / n, 1) << "\n";
    }
    std::cerr << "  stages 2-6  "
              << Fixed(
                     (v.classify_ms + v.encode_ms + v.regions_ms + v.camera_ms + totals.detect_ms) /
                         n,
                     3)
              << " ms\n";
  }
  if (failed > 0) {
    std::cerr << "patlab detect: " << failed << " of " << frames.size() << " frame(s) failed\n";
    return kExitBadInput;
  }
  return kExitOk;
}

PATLAB_REGISTER_COMMAND("detect", "find patterns in camera frames (CMVision regions -> detector)",
                        RunDetect);

}  // namespace patlab::cli

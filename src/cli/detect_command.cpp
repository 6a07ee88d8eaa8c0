// patlab detect: real frames -> vision::FrameDetector (stages of vision/pipeline.h, with the
// detector's own stages of detect/detector.h) -> detections or blobs as CSV or JSON
// (vision::FrameResultsWriter). This file parses flags, calls the library and prints.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>
#include <map>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_results.h"
#include "patlab/vision/segment.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;

constexpr const char* kDetectExamples = R"(examples:
  patlab detect frame/frame.png -t ssl-frame.thresholds -c ssl-frame.calibration \
      -s ssl-frame.detector --debug debug       # after: patlab render ssl-frame -o frame
  patlab detect cam.yuv --raw-size 780x580 -t colors.txt -c cal.toml --blobs
  patlab detect list.txt -t t.toml -c cal.toml --format json -o det --timing   # det/detections.json
  patlab detect frames/ -t t.toml -c cal.toml -s det.toml -o run --track   # + run/track.csv

FRAME arguments: PNG, JPEG or binary PPM files; raw UYVY files (.yuv .uyvy .raw, with --raw-size);
directories (their frames, sorted by name); or a .txt/.list file naming one frame per line.
Without --settings (no patterns to detect) the calibrated blobs are written instead of detections.
Output is written only when every frame succeeded; with --keep-going a bad frame is reported on
stderr, skipped, and the exit status is 2 after the rest is written. --debug DIR writes each
frame's per-stage images as it goes: FRAME.2_colour_lookup.png, FRAME.4_regions.png,
FRAME.5_blobs_to_mm.png and, with --settings, FRAME.6_detect.png.
Exit status: 0 ok, 1 cannot write results, 2 bad input.
)";

struct DetectOptions {
  std::vector<std::string> frames;
  std::string thresholds;
  std::string calibration;
  std::string settings;
  std::string setup;  // --setup DIR: the three files of a patlab setup folder
  std::string raw_size;
  std::string format = "csv";
  std::string out;
  bool track = false;
  std::string track_path;  // DIR/track.csv with --track
  bool quiet = false;
  bool blobs = false;
  bool keep_going = false;
  double edge_loss_px = 0.0;  // --edge-loss-px, when given (it overrides the settings' [frame])
  vision::FrameDetectorOptions frame;
};

void ParseRawSize(const std::string& text, int* width, int* height) {
  const size_t x = text.find('x');
  bool parsed = false;
  try {
    size_t used_w = 0, used_h = 0;
    if (x != std::string::npos) {
      *width = std::stoi(text.substr(0, x), &used_w);
      *height = std::stoi(text.substr(x + 1), &used_h);
      parsed = used_w == x && used_h == text.size() - x - 1 && *width > 0 && *height > 0;
    }
  } catch (const std::exception&) {
  }
  if (!parsed) {
    throw InputError("--raw-size is '" + text + "'; expected WIDTHxHEIGHT, e.g. 780x580");
  }
  const int64_t pixels = int64_t{*width} * *height;
  if (pixels > vision::kMaxFramePixels) {
    throw InputError("--raw-size is '" + text + "', " + std::to_string(pixels) +
                     " pixels; expected at most " + std::to_string(vision::kMaxFramePixels) +
                     " pixels (the frame budget)");
  }
}

po::options_description Flags(DetectOptions* o) {
  po::options_description visible(
      "patlab detect FRAME... --thresholds FILE --calibration FILE [options]");
  visible.add_options()("help,h", "show this help")(
      "thresholds,t", po::value(&o->thresholds),
      "colour thresholds: CMVision colors.txt or our TOML form (required)")(
      "calibration,c", po::value(&o->calibration),
      "camera calibration TOML: pinhole or homography, plane heights (required)")(
      "setup", po::value(&o->setup),
      "a folder written by patlab setup: its calibration, thresholds and settings (instead of "
      "-t, -c and -s)")(
      "settings,s", po::value(&o->settings),
      "detector settings TOML (palette, patterns, options; e.g. experiments/detector.toml)")(
      "raw-size", po::value(&o->raw_size), "WIDTHxHEIGHT of raw UYVY frames (.yuv .uyvy .raw)")(
      "format", po::value(&o->format), "csv (default) or json: what stdout or --out gets")(
      "out,o", po::value(&o->out),
      "output directory: DIR/detections.csv (.json; blobs.csv with --blobs), atomically "
      "(default: stdout)")(
      "track", po::bool_switch(&o->track),
      "also write DIR/track.csv: the frames' robots as a track for patlab analyze (needs --out "
      "and --settings)")("blobs", po::bool_switch(&o->blobs),
                         "write the calibrated blobs instead of detections")(
      "debug", po::value(&o->frame.debug_dir),
      "write each frame's numbered per-stage debug PNGs into this directory")(
      "explain", po::bool_switch(&o->frame.explain),
      "on stderr, every key candidate and why it is a detection or not (docs/detect.md)")(
      "timing", po::bool_switch(&o->frame.collect_timing),
      "per-stage timing and counters on stderr")("keep-going", po::bool_switch(&o->keep_going),
                                                 "report a bad frame and go on with the rest")(
      "min-area-px", po::value(&o->frame.segmenter.min_area_px),
      "drop regions with fewer pixels (default 4)")(
      "min-fill", po::value(&o->frame.segmenter.min_fill),
      "drop regions filling less of their bounding box (default 0)")(
      "edge-loss-px", po::value(&o->edge_loss_px),
      "pixels a region loses around its patch, for the area test (default: the settings' [frame] "
      "edge_loss_px, else 1)");
  AddQuiet(visible.add_options(), &o->quiet);
  return visible;
}

// --track writes DIR/track.csv (docs/cli.md: outputs go into --out); it takes no file name, so
// a .csv among the frames is the old form `--track FILE`.
void CheckTrack(const DetectOptions& o) {
  for (const std::string& frame : o.frames) {
    if (fs::path(frame).extension() == ".csv") {
      throw InputError("--track takes no file name ('" + EscapeForMessage(frame) +
                       "' is not a frame); expected --track --out DIR, which writes DIR/track.csv");
    }
  }
  if (o.out.empty()) {
    throw InputError("--track needs --out; expected --out DIR, where track.csv is written");
  }
  if (o.settings.empty()) {
    throw InputError("--track needs --settings; expected detector settings naming the patterns");
  }
}

void CheckRequired(DetectOptions* o) {
  if (o->frames.empty())
    throw InputError("no frames; expected 'patlab detect FRAME...' (see --help)");
  if (!o->setup.empty()) {
    if (!o->thresholds.empty() || !o->calibration.empty() || !o->settings.empty()) {
      throw InputError("--setup with -t, -c or -s; expected either --setup DIR or the three files");
    }
    const formats::SetupFiles f = formats::LoadSetupFiles(o->setup);
    o->thresholds = f.thresholds;
    o->calibration = f.calibration;
    o->settings = f.settings;
  }
  if (o->thresholds.empty())
    throw InputError("missing --thresholds FILE; expected a colors.txt or thresholds TOML file");
  if (o->calibration.empty())
    throw InputError("missing --calibration FILE; expected a calibration TOML file");
  CheckFormat(o->format, "csv|json");
  o->thresholds = FindData(o->thresholds, io::DataKind::kSettings);
  o->calibration = FindData(o->calibration, io::DataKind::kSettings);
  if (!o->settings.empty()) o->settings = FindData(o->settings, io::DataKind::kSettings);
  if (o->track) CheckTrack(*o);
  if (!o->out.empty()) {
    o->track_path = o->track ? (fs::path(o->out) / "track.csv").string() : "";
    o->out = (fs::path(o->out) / ((o->blobs ? "blobs." : "detections.") + o->format)).string();
  }
  if (!o->raw_size.empty()) {
    ParseRawSize(o->raw_size, &o->frame.raw_width_px, &o->frame.raw_height_px);
  }
  vision::Validate(o->frame.segmenter);
}

// --edge-loss-px as the settings' [frame] edge_loss_px is checked, the message naming the flag.
void CheckEdgeLoss(double edge_loss_px) {
  const std::vector<OptionsProblem> problems =
      detect::Check(detect::FrameSettings{edge_loss_px, {}, {}, {}});
  if (!problems.empty()) {
    std::string message = "--edge-loss-px";
    message.append(problems.front().message, problems.front().field.size());
    throw InputError(message);
  }
}

// With --debug every frame's images are named after its file name without the extension, so two
// frames with the same stem would overwrite each other's images.
void CheckDistinctStems(const std::vector<std::string>& paths) {
  std::map<std::string, std::string> seen;
  for (const std::string& path : paths) {
    const auto [it, inserted] = seen.emplace(fs::path(path).stem().string(), path);
    if (!inserted) {
      throw InputError("--debug: frames " + EscapeForMessage(it->second) + " and " +
                       EscapeForMessage(path) + " have the same name '" +
                       EscapeForMessage(it->first) +
                       "'; expected frames with distinct file names (their debug images are "
                       "named after them)");
    }
  }
}

// The debug directory is checked before any work: not one of the output files (its images would
// be written and the results then refused) and not an existing file.
void CheckDebugDir(const std::string& debug_dir, const std::vector<std::string>& outputs) {
  std::error_code ec;
  const fs::path debug = fs::weakly_canonical(fs::absolute(debug_dir, ec), ec);
  for (const std::string& out : outputs) {
    std::error_code out_ec;
    if (!out.empty() && fs::weakly_canonical(fs::absolute(out, out_ec), out_ec) == debug) {
      throw InputError("--debug " + EscapeForMessage(debug_dir) + " is the output file " +
                       EscapeForMessage(out) +
                       "; expected a debug directory apart from the output files");
    }
  }
  if (fs::exists(debug_dir, ec) && !fs::is_directory(debug_dir, ec)) {
    // As an output file whose path is a directory: an unusable output location, exit 1.
    throw EnvironmentError(EscapeForMessage(debug_dir, 1024) +
                           ": cannot write: it is a file; expected a directory for the debug "
                           "images");
  }
}

// Sums of the frames' counters and stage times, for --timing.
struct Totals {
  int frames = 0;
  vision::VisionStats vision;
  detect::DetectStats detect;
  TimeProfile profile{true}, detect_profile{true};

  void Add(const vision::FrameResult& r) {
    ++frames;
    vision += r.vision_stats;
    detect += r.detect_stats;
    profile += r.profile;
    detect_profile += r.detect_profile;
  }
};

// The counters printed beside a stage's time, per frame.
std::string Counters(std::string_view stage, const Totals& t) {
  const double n = t.frames;
  auto per_frame = [n](long count, int decimals) { return FormatFixed(count / n, decimals); };
  const vision::VisionStats& v = t.vision;
  const detect::DetectStats& d = t.detect;
  if (stage == "3 runs") return "runs " + per_frame(v.runs, 0);
  if (stage == "4 regions") {
    return "regions " + per_frame(v.raw_regions, 0) + " -> kept " + per_frame(v.regions, 0);
  }
  if (stage == "5 blobs to mm") {
    return "blobs " + per_frame(v.blobs, 0) + " (off plane " + per_frame(v.off_plane, 0) + ")";
  }
  if (stage == "6 detect") return "detections " + per_frame(d.detections, 1);
  if (stage == "1 candidates") return "key candidates " + per_frame(d.key_candidates, 1);
  if (stage == "2 neighbours") {
    return "found " + per_frame(d.neighbours, 1) + " (cut " + per_frame(d.neighbours_cut, 1) + ")";
  }
  if (stage == "4 fit rotations") {
    return "rotations " + per_frame(d.correspondences, 1) + ", geometry passed " +
           per_frame(d.geometry_passed, 1);
  }
  if (stage == "5 identify") {
    return "colour rejected " + per_frame(d.colour_rejected, 1) + ", ambiguous " +
           per_frame(d.ambiguous, 1);
  }
  if (stage == "6 missing patch") return "missing patch " + per_frame(d.missing_fits, 1);
  if (stage == "7 conflicts") return "dropped " + per_frame(d.conflicts, 1);
  if (stage == "8 pose") return "detections " + per_frame(d.detections, 1);
  return "";
}

// One table: the frame's stages (vision/pipeline.h), the detector's (detect/detector.h) indented
// under "6 detect", each with its time and counters per frame, names as the headers number them.
void PrintTiming(const Totals& t) {
  const double n = t.frames;
  auto row = [&](const char* indent, const TimeProfile::Entry& e) {
    const std::string counters = Counters(e.stage, t);
    std::cerr << StringPrintf("%s%-16s %9s ms", indent, std::string(e.stage).c_str(),
                              FormatFixed(e.seconds * 1e3 / n, 4).c_str())
              << (counters.empty() ? "" : "  " + counters) << "\n";
  };
  std::cerr << "patlab detect: " << t.frames << " frame(s), per frame:\n";
  for (const TimeProfile::Entry& e : t.profile.entries()) {
    row("  ", e);
    if (e.stage != "6 detect") continue;
    for (const TimeProfile::Entry& d : t.detect_profile.entries()) row("      ", d);
  }
  std::cerr << StringPrintf("  %-16s %9s ms\n", "total",
                            FormatFixed(t.profile.total_seconds() * 1e3 / n, 4).c_str());
}

}  // namespace

// The help's option groups (command_line.h).
const OptionGroups kDetectGroups = {
    {"input", {"setup", "thresholds", "calibration", "settings", "raw-size"}},
    {"detector", {"min-area-px", "min-fill", "edge-loss-px"}},
    {"output", {"out", "format", "blobs", "track"}},
    {"diagnostics", {"debug", "explain", "timing"}},
    {"run", {"keep-going", "quiet"}}};

int RunDetect(const std::vector<std::string>& args) {
  DetectOptions o;
  const po::options_description visible = Flags(&o);
  po::variables_map vm;
  if (!ParseArguments(args, visible, kDetectGroups, "frame", po::value(&o.frames), -1,
                      kDetectExamples, &vm)) {
    return kExitOk;
  }
  ThrowFlagProblem(vision::Check(o.frame.segmenter), vm,
                   {{"min_area_px", "--min-area-px"}, {"min_fill", "--min-fill"}});
  CheckRequired(&o);
  if (vm.count("edge-loss-px") > 0) CheckEdgeLoss(o.edge_loss_px);
  if (!o.out.empty()) io::CheckWritable({o.out});
  if (o.track) io::CheckWritable({o.track_path});
  if (!o.frame.debug_dir.empty()) CheckDebugDir(o.frame.debug_dir, {o.out, o.track_path});
  std::optional<detect::DetectorConfig> settings;
  if (!o.settings.empty()) {
    settings = formats::LoadDetectorSettings(o.settings);
    vision::ApplyFrameSettings(formats::LoadFrameSettings(o.settings), &o.frame);
  }
  if (vm.count("edge-loss-px") > 0) o.frame.edge_loss_px = o.edge_loss_px;
  vision::FrameDetector frames(formats::LoadThresholds(o.thresholds),
                               formats::LoadCalibration(o.calibration), std::move(settings),
                               o.frame);
  for (const std::string& warning : frames.warnings()) {
    std::cerr << "patlab detect: warning: " << warning << "\n";
  }
  vision::FrameResultsWriter writer(frames, o.blobs);
  std::optional<vision::TrackWriter> track;
  if (o.track) track.emplace(frames);
  const std::vector<std::string> paths = vision::ExpandFrameList(o.frames);
  if (!o.frame.debug_dir.empty()) CheckDistinctStems(paths);
  Totals totals;
  int failed = 0;
  Progress progress("patlab detect", "frames", !o.quiet, StderrIsTerminal());
  const int total = static_cast<int>(paths.size());
  for (size_t index = 0; index < paths.size(); ++index) {
    const std::string& path = paths[index];
    try {
      const vision::FrameResult& result = frames.DetectFile(path);
      writer.Add(result);
      if (track) track->Add(static_cast<int64_t>(index), result);
      totals.Add(result);
      std::cerr << vision::ExplanationText(result, frames);
    } catch (const InputError& e) {
      if (!o.keep_going) throw;
      ++failed;
      std::cerr << "patlab detect: " << e.what() << " (skipped: --keep-going)\n";
    }
    progress.Update(static_cast<int>(index) + 1, total);
  }
  const std::string output = o.format == "csv" ? writer.Csv() : writer.Json();
  if (!o.out.empty() || track) {
    try {
      std::vector<std::pair<std::string, std::string>> files;
      if (track) files.emplace_back(o.track_path, track->Csv());
      if (!o.out.empty()) files.emplace_back(o.out, output);
      io::WriteFilesAtomic(files);
    } catch (const std::exception& e) {
      std::cerr << "patlab detect: " << e.what() << "\n";
      return kExitFailure;
    }
  }
  if (o.out.empty()) std::cout << output;
  if (o.frame.collect_timing && totals.frames > 0) PrintTiming(totals);
  if (failed > 0) {
    std::cerr << "patlab detect: " << failed << " of " << paths.size() << " frame(s) failed\n";
    return kExitBadInput;
  }
  return kExitOk;
}

PATLAB_REGISTER_COMMAND("detect", "find patterns in camera frames (CMVision regions -> detector)",
                        RunDetect);

}  // namespace patlab::cli

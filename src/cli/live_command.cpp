// patlab live: camera sources -> live::RunLive (one capture and one detection thread per camera)
// -> SSL-Vision packets by UDP, an SSL log, JSON lines. This file parses flags, calls the library
// and prints.
#include <boost/program_options.hpp>
#include <csignal>
#include <fstream>
#include <iostream>
#include <optional>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/live/live_loop.h"
#include "patlab/live/ssl_log.h"
#include "patlab/live/udp_sender.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

CommandHelp Help() {
  return {
      "patlab live SOURCE... -t FILE -c FILE [-s FILE] [options]",
      "Runs the detector on camera frames as they come and sends the detections as SSL-Vision "
      "packets (SSL_WrapperPacket protobuf messages: a detection frame per camera and frame, "
      "the field geometry once a second) by UDP, to an SSL log and as JSON lines "
      "(docs/live.md).\n\n"
      "SOURCE arguments: a V4L2 device (/dev/videoN; untested here, docs/live.md), a video "
      "file (.mp4 .mkv .avi .mov .webm ...; FFmpeg), or frames as patlab detect reads them "
      "(files, a directory, a .txt list). Each SOURCE is a camera; -t, -c and -s are given "
      "once for all or once per SOURCE in order, as files or shipped names; camera ids are "
      "0, 1, ... unless --camera-id says otherwise. SIGINT or SIGTERM stops the loop; the log "
      "is then closed whole. A corrupt frame is skipped and counted, a camera that fails is "
      "reopened with a back-off, a packet the system refuses is sent again; each is reported "
      "on stderr. Exit status: 0 ok (frames skipped included), 1 an output failed, 2 bad "
      "input.",
      "  patlab live /dev/video0 -t colors.toml -c cal.toml -s detector.toml --field ssl-div-b\n"
      "  patlab live frame.png --loop --max-frames 100 -t ssl-frame.thresholds \\\n"
      "      -c ssl-frame.calibration -s ssl-frame.detector --send 127.0.0.1:10006 --stats\n"
      "  patlab live left.mp4 right.mp4 -t t.toml -c left.toml -c right.toml -s s.toml \\\n"
      "      --send 127.0.0.1:10006 --log match.log --jsonl -\n"};
}

struct LiveCommandOptions {
  std::vector<std::string> sources, thresholds, calibrations, settings;
  std::string camera_ids, send = "224.5.23.2:10006", iface, log, jsonl, field, rate = "native",
                          raw_size;
  int ttl = 1;
  long max_frames = 0;
  double list_rate_hz = 60.0;
  bool loop = false, stats = false, hold_ids = false;
};

void AddFlags(CommandLine* line, LiveCommandOptions* o) {
  line->Group("cameras")("thresholds,t", po::value(&o->thresholds)->composing(),
                         "colour thresholds (required; once, or once per SOURCE)")(
      "calibration,c", po::value(&o->calibrations)->composing(),
      "camera calibration TOML (required; once, or once per SOURCE)")(
      "settings,s", po::value(&o->settings)->composing(),
      "detector settings TOML (once, or once per SOURCE; without: balls only)")(
      "camera-id", po::value(&o->camera_ids),
      "comma-separated SSL camera ids, one per SOURCE (default 0, 1, ...)")(
      "raw-size", po::value(&o->raw_size), "WIDTHxHEIGHT of raw UYVY frame files");
  line->Group("pace")("rate", po::value(&o->rate),
                      "native (each source at its own pace, default) or max")(
      "list-rate", po::value(&o->list_rate_hz), "frames per second of a frame list (default 60)")(
      "loop", po::bool_switch(&o->loop), "start a frame list again after its last frame")(
      "max-frames", po::value(&o->max_frames), "stop each source after N frames (default 0: none)");
  line->Group("packets")("send", po::value(&o->send),
                         "ADDRESS:PORT to send packets to (default 224.5.23.2:10006)")(
      "ttl", po::value(&o->ttl), "multicast TTL, 0..255 (default 1: this network)")(
      "iface", po::value(&o->iface), "multicast interface: its IPv4 address or name")(
      "field", po::value(&o->field),
      "field TOML or shipped name for the geometry packet, once a second (without: none)")(
      "hold-ids", po::bool_switch(&o->hold_ids),
      "keep a tracked robot's ID through up to 2 frames read as unknown or another ID (marked "
      "id_held in --jsonl; docs/live.md)");
  line->Group("outputs")("log", po::value(&o->log), "also write every packet to this SSL log file")(
      "jsonl", po::value(&o->jsonl), "also write one JSON object per frame to FILE or - (stdout)")(
      "stats", po::bool_switch(&o->stats),
      "on stderr at the end: frames received/processed/dropped, latency p50/p99/max per stage");
}

// A per-camera file flag: once for every camera, or once per camera.
std::string PerCamera(const std::vector<std::string>& values, size_t camera, size_t cameras,
                      const char* flag, bool required) {
  if (values.empty()) {
    if (!required) return "";
    throw InputError(std::string("missing ") + flag + " FILE; expected one for all SOURCEs or " +
                     "one per SOURCE");
  }
  if (values.size() != 1 && values.size() != cameras) {
    throw InputError(std::string(flag) + " is given " + std::to_string(values.size()) +
                     " times for " + std::to_string(cameras) +
                     " SOURCE(s); expected once or once per SOURCE");
  }
  return values[values.size() == 1 ? 0 : camera];
}

std::vector<uint32_t> CameraIds(const LiveCommandOptions& o) {
  std::vector<uint32_t> ids;
  if (o.camera_ids.empty()) {
    for (size_t i = 0; i < o.sources.size(); ++i) ids.push_back(static_cast<uint32_t>(i));
    return ids;
  }
  for (int id : ParseIntegerList(o.camera_ids, "--camera-id", 0, 1 << 30,
                                 "comma-separated integers >= 0, one per SOURCE")) {
    ids.push_back(static_cast<uint32_t>(id));
  }
  if (ids.size() != o.sources.size()) {
    throw InputError("--camera-id has " + std::to_string(ids.size()) + " id(s) for " +
                     std::to_string(o.sources.size()) + " SOURCE(s); expected one per SOURCE");
  }
  return ids;
}

void ParseRawSize(const std::string& text, live::FrameSourceOptions* source) {
  const size_t x = text.find('x');
  std::vector<int> size;
  if (x != std::string::npos) {
    try {
      size = ParseIntegerList(text.substr(0, x) + "," + text.substr(x + 1), "--raw-size", 1,
                              1 << 16, "");
    } catch (const InputError&) {
    }
  }
  if (size.size() != 2) {
    throw InputError("--raw-size is '" + text + "'; expected WIDTHxHEIGHT, e.g. 780x580");
  }
  source->raw_width_px = size[0];
  source->raw_height_px = size[1];
}

std::vector<live::LiveCamera> Cameras(const LiveCommandOptions& o) {
  const std::vector<uint32_t> ids = CameraIds(o);
  std::vector<live::LiveCamera> cameras;
  const size_t n = o.sources.size();
  for (size_t i = 0; i < n; ++i) {
    live::LiveCamera camera;
    camera.source = o.sources[i];
    camera.camera_id = ids[i];
    camera.thresholds = formats::LoadThresholds(
        FindData(PerCamera(o.thresholds, i, n, "--thresholds", true), io::DataKind::kSettings));
    camera.calibration = formats::LoadCalibration(
        FindData(PerCamera(o.calibrations, i, n, "--calibration", true), io::DataKind::kSettings));
    std::string settings = PerCamera(o.settings, i, n, "--settings", false);
    if (!settings.empty()) {
      settings = FindData(settings, io::DataKind::kSettings);
      camera.detector = formats::LoadDetectorSettings(settings);
      vision::ApplyFrameSettings(formats::LoadFrameSettings(settings), &camera.frame);
    }
    camera.frame.raw_width_px = 0;  // raw frames are read by the source, not the detector
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

std::atomic<bool> g_stop{false};
extern "C" void OnStopSignal(int) { g_stop.store(true); }

void PrintStats(const live::LiveStats& s) {
  std::cerr << "patlab live: frames received " << s.received << ", processed " << s.processed
            << ", dropped " << s.dropped << ", skipped corrupt " << s.skipped << "; reopens "
            << s.reopens << "; packets " << s.packets << " detection, " << s.geometry_packets
            << " geometry, " << s.send_failures << " not sent, " << s.send_retries
            << " retries; ids held " << s.ids_held << "\n";
  if (s.cameras.size() > 1) {
    for (const live::CameraFrameCounts& c : s.cameras) {
      std::cerr << "  camera " << c.camera_id << ": frames received " << c.received
                << ", processed " << c.processed << ", dropped " << c.dropped
                << ", skipped corrupt " << c.skipped << "\n";
    }
  }
  std::cerr << StringPrintf("  %-12s %9s %9s %9s\n", "stage", "p50 ms", "p99 ms", "max ms");
  for (const live::StageLatency& l : s.latency) {
    std::cerr << StringPrintf("  %-12s %9s %9s %9s\n", l.stage.c_str(),
                              FormatFixed(l.p50_ms, 3).c_str(), FormatFixed(l.p99_ms, 3).c_str(),
                              FormatFixed(l.max_ms, 3).c_str());
  }
}

live::LiveOptions LoopOptions(const LiveCommandOptions& o) {
  live::LiveOptions options;
  options.rate = ParseName(o.rate, live::kLiveRateNames, "--rate");
  if (o.max_frames < 0) {
    throw InputError("--max-frames is " + std::to_string(o.max_frames) + "; expected >= 0");
  }
  if (!(o.list_rate_hz > 0.0)) {
    throw InputError("--list-rate is " + FormatNumber(o.list_rate_hz) +
                     "; expected > 0 frames per second");
  }
  options.max_frames = o.max_frames;
  options.hold_ids.enabled = o.hold_ids;
  options.source.loop = o.loop;
  options.source.list_rate_hz = o.list_rate_hz;
  if (!o.raw_size.empty()) ParseRawSize(o.raw_size, &options.source);
  return options;
}

}  // namespace

int RunLiveCommand(const std::vector<std::string>& args) {
  LiveCommandOptions o;
  CommandLine line("live", Help());
  AddFlags(&line, &o);
  line.Positional("source", po::value(&o.sources), -1);
  po::variables_map vm;
  if (!line.Parse(args, &vm)) return kExitOk;
  if (o.sources.empty())
    throw InputError("no SOURCE; expected 'patlab live SOURCE...' (see --help)");
  const live::LiveOptions options = LoopOptions(o);
  const live::UdpAddress address = live::ParseUdpAddress(o.send, "--send");
  const std::vector<live::LiveCamera> cameras = Cameras(o);
  live::LiveOutputs outputs;
  if (!o.field.empty()) outputs.field = formats::LoadField(FindData(o.field, io::DataKind::kField));
  live::UdpSender sender(address, live::UdpSenderOptions{o.ttl, o.iface, true});
  outputs.sender = &sender;
  std::optional<live::SslLogWriter> log;
  if (!o.log.empty()) outputs.log = &log.emplace(o.log);
  std::ofstream jsonl_file;
  if (!o.jsonl.empty()) {
    std::ostream* out = &std::cout;
    if (o.jsonl != "-") {
      jsonl_file.open(o.jsonl, std::ios::binary | std::ios::trunc);
      if (!jsonl_file) throw EnvironmentError(o.jsonl + ": cannot create the --jsonl file");
      out = &jsonl_file;
    }
    outputs.jsonl = [out](std::string_view line) { *out << line << '\n' << std::flush; };
  }
  outputs.message = [](std::string_view text) { std::cerr << "patlab live: " << text << '\n'; };
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  const live::LiveStats stats = live::RunLive(cameras, options, outputs, g_stop);
  if (log) log->Close();
  if (o.stats) PrintStats(stats);
  return kExitOk;
}

PATLAB_REGISTER_COMMAND("live", "send detections as SSL-Vision packets (UDP, SSL log, JSON lines)",
                        RunLiveCommand);

}  // namespace patlab::cli

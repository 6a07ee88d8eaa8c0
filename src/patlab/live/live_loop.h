// The live loop of `patlab live`: one capture thread per camera source reading frames at the
// source's pace (or as fast as it can), handing each to that camera's detection thread through a
// one-frame mailbox where the newest frame wins -- a slow detector never holds up capture; a
// frame overwritten before it was taken is counted as dropped -- and the detection thread
// running vision::FrameDetector, building the SSL detection packet (packet.h) and handing it to
// the outputs: the UDP sender, the SSL log, JSON lines. The geometry packet goes out at start and
// then once a period. Stops at the end of every source, after the frame limit, or when `stop`
// becomes true (a signal handler sets it), always with the outputs whole: every packet sent is in
// the log as a whole message.
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/calib/field.h"
#include "patlab/live/frame_source.h"
#include "patlab/live/id_hold.h"
#include "patlab/live/packet.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::live {

class UdpSender;
class SslLogWriter;

// One camera: its source (a SOURCE argument, frame_source.h), its SSL camera id and what its
// frames are detected with.
struct LiveCamera {
  std::string source;
  uint32_t camera_id = 0;
  vision::Thresholds thresholds;
  camera::Calibration calibration;
  std::optional<detect::DetectorConfig> detector;  // nullopt: balls only
  vision::FrameDetectorOptions frame;
};

enum class LiveRate {
  kNative,  // each source at its own pace (SourceFrame::media_time_s)
  kMax,     // as fast as frames can be read
};
inline constexpr EnumNames<LiveRate, 2> kLiveRateNames{
    {{{LiveRate::kNative, "native"}, {LiveRate::kMax, "max"}}}};

struct LiveOptions {
  LiveRate rate = LiveRate::kNative;
  // Frames each source delivers before it stops; 0 = no limit. >= 0.
  long max_frames = 0;
  // Seconds between geometry packets, > 0 (SSL-Vision sends them about once a second).
  double geometry_period_s = 1.0;
  FrameSourceOptions source;
  SslColourNames names;
  // A source that fails while delivering frames (SourceError that can be reopened: a V4L2 device
  // unplugged or failing) is closed and opened again after reopen_delay_s, doubled after each
  // failed attempt up to reopen_max_delay_s (0.1, 0.2, 0.4, ... 3.2, 5, 5, ... s by default), until
  // it delivers a frame again. > 0 and >= reopen_delay_s. Short delays find a camera that comes
  // back sooner; long ones spare a machine whose camera is gone for good.
  double reopen_delay_s = 0.1;
  double reopen_max_delay_s = 5.0;
  // Consecutive failed attempts after which that camera gives up (EnvironmentError, exit status
  // 1); 0: no limit (a camera at a match comes back whenever it can). >= 0.
  long reopen_attempts = 0;
  // Tries per packet and output: a datagram the system refuses (no route, buffer full) is sent
  // again at once, up to this many times in all, then counted as not sent. >= 1.
  int send_attempts = 3;
  IdHoldOptions hold_ids;  // --hold-ids; off by default
};
std::vector<OptionsProblem> Check(const LiveOptions& options);
void Validate(const LiveOptions& options);

// Where packets go; each may be absent. Called from the detection threads, one at a time.
struct LiveOutputs {
  UdpSender* sender = nullptr;
  SslLogWriter* log = nullptr;
  std::function<void(std::string_view json_line)> jsonl;  // one line, without its newline
  std::optional<calib::Field> field;  // the geometry's field; nullopt: no geometry packets
  // What the loop reports as it goes (a source failing and reopened, a frame skipped, sending
  // failing and working again), one line without its newline; `patlab live` prints it on stderr.
  // Called from any thread, one call at a time.
  std::function<void(std::string_view message)> message;
};

// What a test injects; empty members take the defaults.
struct LiveHooks {
  // Opens a camera's source (default OpenFrameSource): a source that fails on purpose.
  std::function<std::unique_ptr<FrameSource>(const std::string& spec,
                                             const FrameSourceOptions& options)>
      open_source;
  // Called by a camera's detection thread with the frame it took, before detecting it: a slow
  // detection stage.
  std::function<void(uint32_t camera_id, int64_t frame_index)> before_detect;
};

// A stage's latency over the frames processed, milliseconds.
struct StageLatency {
  std::string stage;
  double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
};

// The stages a frame goes through, as the latency table names them.
inline constexpr std::array<std::string_view, 5> kLiveStageNames = {
    "1 hand-off", "2 detect", "3 packet", "4 send", "end to end"};

// One camera's frame counts; LiveStats' totals are their sums.
struct CameraFrameCounts {
  uint32_t camera_id = 0;
  long received = 0;   // frames its source delivered
  long processed = 0;  // frames detected and sent
  long dropped = 0;    // received = processed + dropped, as for the totals
  long skipped = 0;    // corrupt frames its source skipped
};

struct LiveStats {
  long received = 0;   // frames the sources delivered
  long processed = 0;  // frames detected and sent
  long dropped = 0;    // frames overwritten in a mailbox before detection took them, or left
                       // there by a stop request: received = processed + dropped
  long skipped = 0;    // corrupt frames the sources skipped (CorruptFrameError); not received
  long reopens = 0;    // times a failed source was opened again (successfully or not)
  long packets = 0;    // detection packets handed to the outputs
  long geometry_packets = 0;
  long send_failures = 0;  // packets the sender did not send after LiveOptions::send_attempts
  long send_retries = 0;   // tries that failed and were tried again
  long ids_held = 0;       // robots sent with an ID carried over (--hold-ids, id_hold.h)
  std::vector<StageLatency> latency;       // kLiveStageNames, in order
  std::vector<CameraFrameCounts> cameras;  // per camera, in the order of RunLive's `cameras`
};

// Cameras' ids must differ (InputError "--camera-id: ... twice; expected one id per camera").
// Runs the loop until every source ends, the frame limit, or `stop`. InputError for a source
// that cannot be opened at the start or a frame file it cannot read (the other cameras stop too);
// EnvironmentError when an output fails or a source stays gone for reopen_attempts attempts.
// Faults that a live source survives do not stop it: a corrupt frame is skipped and counted, a
// failing source reopened with a back-off, a refused packet sent again (LiveOptions), each
// reported through LiveOutputs::message. A file source whose read fails ends there (reported).
LiveStats RunLive(const std::vector<LiveCamera>& cameras, const LiveOptions& options,
                  LiveOutputs& outputs, const std::atomic<bool>& stop, const LiveHooks& hooks = {});

// Seconds before the `attempt`-th (1, 2, ...) consecutive attempt to reopen a failed source:
// min(reopen_delay_s * 2^(attempt - 1), reopen_max_delay_s).
double ReopenDelaySeconds(const LiveOptions& options, long attempt);

// p-th percentile (0..100, nearest rank) of `values`, which it sorts; 0 for none.
double Percentile(std::vector<double>& values, double p);

}  // namespace patlab::live

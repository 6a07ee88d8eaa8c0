// The live loop (live_loop.h): capture threads, newest-frame-wins mailboxes, detection threads
// and the outputs they share.
#include "patlab/live/live_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "patlab/core/error.h"
#include "patlab/live/live_loop_internal.h"
#include "patlab/live/ssl_log.h"
#include "patlab/live/udp_sender.h"

namespace patlab::live {

namespace {

using internal::Clock;
using internal::Mailbox;
using internal::Shared;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

int64_t WallTimeNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Under shared.mutex: one packet through the sender, tried up to send_attempts times; the first
// packet of a run of failures and the first sent after it are reported.
void Send(const std::string& bytes, Shared& shared) {
  UdpSender& sender = *shared.outputs.sender;
  for (int attempt = 1;; ++attempt) {
    if (sender.Send(bytes)) {
      if (shared.send_failing) {
        shared.Report("sending to " + sender.address().host + ":" +
                      std::to_string(sender.address().port) + " works again");
      }
      shared.send_failing = false;
      return;
    }
    if (attempt >= shared.options.send_attempts) break;
    ++shared.stats.send_retries;
  }
  ++shared.stats.send_failures;
  if (!shared.send_failing) {
    shared.Report("sending to " + sender.address().host + ":" +
                  std::to_string(sender.address().port) + " failed: " + sender.last_error() +
                  "; tried " + std::to_string(shared.options.send_attempts) +
                  " times, the packet is counted as not sent and the next ones are tried");
  }
  shared.send_failing = true;
}

// Under shared.mutex: the geometry when it is due, then the detection packet, to every output.
void Emit(const SslDetection& detection, const std::string& bytes, Shared& shared) {
  LiveOutputs& out = shared.outputs;
  const Clock::time_point now = Clock::now();
  const bool geometry_due =
      !shared.geometry_bytes.empty() &&
      (!shared.geometry_sent || std::chrono::duration<double>(now - shared.last_geometry).count() >=
                                    shared.options.geometry_period_s);
  if (geometry_due) {
    if (out.sender) Send(shared.geometry_bytes, shared);
    if (out.log) out.log->Write(WallTimeNs(), SslMessageType::kVision2010, shared.geometry_bytes);
    shared.geometry_sent = true;
    shared.last_geometry = now;
    ++shared.stats.geometry_packets;
  }
  if (out.sender) Send(bytes, shared);
  if (out.log) out.log->Write(WallTimeNs(), SslMessageType::kVision2010, bytes);
  if (out.jsonl) out.jsonl(DetectionJson(detection));
  ++shared.stats.packets;
}

// Takes the waiting frame into `image`; false when the source has ended and nothing waits.
bool Take(Mailbox& box, camera::Image* image, FrameStamp* stamp, Clock::time_point* delivered,
          Clock::time_point* put) {
  std::unique_lock lock(box.mutex);
  box.ready.wait(lock, [&] { return box.full || box.closed; });
  if (!box.full) return false;
  std::swap(*image, box.image);
  box.full = false;
  stamp->frame_number = static_cast<uint32_t>(box.index);
  stamp->t_capture_s = box.capture_time_s;
  *delivered = box.delivered_at;
  *put = box.put_at;
  return true;
}

void DetectFrames(vision::FrameDetector& frames, uint32_t camera_id, Mailbox& box, Shared& shared) {
  IdHolder holder(shared.options.hold_ids);
  camera::Image image;
  FrameStamp stamp;
  stamp.camera_id = camera_id;
  Clock::time_point delivered, put;
  const std::string name = "camera " + std::to_string(camera_id);
  while (!shared.Stopping() && Take(box, &image, &stamp, &delivered, &put)) {
    const Clock::time_point taken = Clock::now();
    if (shared.hooks.before_detect) shared.hooks.before_detect(camera_id, stamp.frame_number);
    const vision::FrameResult& result = frames.Detect(image, name);
    const Clock::time_point detected = Clock::now();
    stamp.t_sent_s = WallTimeSeconds();
    SslDetection detection = DetectionOfFrame(result, frames, stamp, shared.options.names);
    const int held = holder.Apply(&detection);
    const std::string bytes = SerializeDetection(detection);
    const Clock::time_point packed = Clock::now();
    std::lock_guard lock(shared.mutex);
    shared.stats.ids_held += held;
    Emit(detection, bytes, shared);
    const Clock::time_point sent = Clock::now();
    const std::array<double, kLiveStageNames.size()> ms = {Ms(taken - put), Ms(detected - taken),
                                                           Ms(packed - detected), Ms(sent - packed),
                                                           Ms(sent - delivered)};
    for (size_t i = 0; i < ms.size(); ++i) shared.samples_ms[i].push_back(ms[i]);
    ++shared.stats.processed;
    ++box.processed;
  }
}

void DetectThread(vision::FrameDetector& frames, uint32_t camera_id, Mailbox& box, Shared& shared) {
  try {
    DetectFrames(frames, camera_id, box, shared);
  } catch (...) {
    shared.Fail();
  }
}

void Summarise(const std::vector<LiveCamera>& cameras,
               const std::vector<std::unique_ptr<Mailbox>>& boxes, Shared& shared) {
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Mailbox& box = *boxes[i];
    // A frame still waiting when a stop request ended the loop was not processed either.
    const CameraFrameCounts counts{cameras[i].camera_id, box.received, box.processed,
                                   box.dropped + (box.full ? 1 : 0), box.skipped};
    shared.stats.cameras.push_back(counts);
    shared.stats.received += counts.received;
    shared.stats.dropped += counts.dropped;
    shared.stats.skipped += counts.skipped;
    shared.stats.reopens += box.reopens;
  }
  for (size_t i = 0; i < kLiveStageNames.size(); ++i) {
    std::vector<double>& v = shared.samples_ms[i];
    const double max_ms = v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
    shared.stats.latency.push_back(
        {std::string(kLiveStageNames[i]), Percentile(v, 50), Percentile(v, 99), max_ms});
  }
}

void CheckCameraIds(const std::vector<LiveCamera>& cameras) {
  for (size_t i = 0; i < cameras.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (cameras[i].camera_id == cameras[j].camera_id) {
        throw InputError("--camera-id: camera id " + std::to_string(cameras[i].camera_id) +
                         " is given twice; expected one id per camera");
      }
    }
  }
}

}  // namespace

std::vector<OptionsProblem> Check(const LiveOptions& options) {
  return OptionsChecker()
      .IntegerInRange("max_frames", options.max_frames, 0, INT64_MAX)
      .Positive("geometry_period_s", options.geometry_period_s, "s")
      .Positive("list_rate_hz", options.source.list_rate_hz, "Hz")
      .Positive("reopen_delay_s", options.reopen_delay_s, "s")
      .Require("reopen_max_delay_s", options.reopen_max_delay_s,
               options.reopen_max_delay_s >= options.reopen_delay_s, ">= reopen_delay_s")
      .IntegerInRange("reopen_attempts", options.reopen_attempts, 0, INT64_MAX)
      .IntegerInRange("send_attempts", options.send_attempts, 1, 1000)
      .Take();
}

void Validate(const LiveOptions& options) {
  ThrowFirstProblem(Check(options));
  live::Validate(options.hold_ids);
}

double Percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(p / 100.0 * static_cast<double>(values.size()));
  const size_t index = rank < 1.0 ? 0 : static_cast<size_t>(rank) - 1;
  return values[std::min(index, values.size() - 1)];
}

LiveStats RunLive(const std::vector<LiveCamera>& cameras, const LiveOptions& options,
                  LiveOutputs& outputs, const std::atomic<bool>& stop, const LiveHooks& hooks) {
  Validate(options);
  CheckCameraIds(cameras);
  std::vector<vision::FrameDetector> detectors;
  SslGeometry geometry;
  if (outputs.field) geometry = GeometryOf(*outputs.field, {});
  for (const LiveCamera& camera : cameras) {
    detectors.emplace_back(camera.thresholds, camera.calibration, camera.detector, camera.frame);
    if (auto c = CameraCalibrationOf(camera.calibration, camera.camera_id)) {
      geometry.cameras.push_back(*c);
    }
  }
  Shared shared(options, outputs, stop, hooks);
  if (outputs.field) shared.geometry_bytes = SerializeGeometry(geometry);
  std::vector<std::unique_ptr<Mailbox>> boxes;
  for (size_t i = 0; i < cameras.size(); ++i) boxes.push_back(std::make_unique<Mailbox>());
  {
    std::vector<std::jthread> threads;
    for (size_t i = 0; i < cameras.size(); ++i) {
      threads.emplace_back(internal::CaptureThread, std::cref(cameras[i].source),
                           cameras[i].camera_id, std::ref(*boxes[i]), std::ref(shared));
      threads.emplace_back(DetectThread, std::ref(detectors[i]), cameras[i].camera_id,
                           std::ref(*boxes[i]), std::ref(shared));
    }
  }
  if (shared.error) std::rethrow_exception(shared.error);
  Summarise(cameras, boxes, shared);
  return shared.stats;
}

}  // namespace patlab::live

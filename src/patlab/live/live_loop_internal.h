// What the pieces of the live loop share (live_loop.cpp: the detection threads, the outputs and
// the summary; live_capture.cpp: the capture threads and their faults). Not installed.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <string_view>

#include "patlab/live/live_loop.h"

namespace patlab::live::internal {

using Clock = std::chrono::steady_clock;

// One camera's hand-off: at most one frame waits; a newer one replaces it (counted as dropped).
struct Mailbox {
  std::mutex mutex;
  std::condition_variable ready;
  camera::Image image;
  double capture_time_s = 0.0;
  int64_t index = 0;
  Clock::time_point delivered_at, put_at;
  bool full = false;
  bool closed = false;
  long received = 0;
  long dropped = 0;
  long skipped = 0;  // corrupt frames the source skipped
  long reopens = 0;
  long processed = 0;  // written by the detection thread under Shared::mutex, read after join
};

// What the threads share: the outputs and the counters under one mutex, the first error.
struct Shared {
  Shared(const LiveOptions& o, LiveOutputs& out, const std::atomic<bool>& s, const LiveHooks& h)
      : options(o), outputs(out), stop(s), hooks(h) {}
  const LiveOptions& options;
  LiveOutputs& outputs;
  const std::atomic<bool>& stop;
  const LiveHooks& hooks;
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::exception_ptr error;
  std::string geometry_bytes;
  bool geometry_sent = false;
  bool send_failing = false;  // the last packet was not sent (reported once per run of failures)
  Clock::time_point last_geometry;
  LiveStats stats;
  std::array<std::vector<double>, kLiveStageNames.size()> samples_ms;
  std::mutex message_mutex;

  bool Stopping() const { return stop.load() || failed.load(); }
  void Fail() {
    std::lock_guard lock(mutex);
    if (!error) error = std::current_exception();
    failed = true;
  }
  // One line to LiveOutputs::message, if any; not under `mutex` (Emit reports while holding it).
  void Report(std::string_view text) {
    if (!outputs.message) return;
    std::lock_guard lock(message_mutex);
    outputs.message(text);
  }
};

// Sleeps until `when` in short steps, so that a stop request is seen within 20 ms.
void SleepUntil(Clock::time_point when, const Shared& shared);

// A camera's capture thread: opens its source, reads frames at the pace asked for into `box`,
// skips corrupt frames, reopens a failed source; closes `box` at the end.
void CaptureThread(const std::string& spec, uint32_t camera_id, Mailbox& box, Shared& shared);

}  // namespace patlab::live::internal

// The capture side of the live loop (live_loop_internal.h): a source's frames into its mailbox,
// and the faults a live source survives -- a corrupt frame skipped and counted, a failing source
// reopened with an exponential back-off (live_loop.h, docs/live.md).
#include <algorithm>
#include <cmath>
#include <thread>

#include "patlab/core/format.h"
#include "patlab/live/live_loop_internal.h"

namespace patlab::live {

double ReopenDelaySeconds(const LiveOptions& options, long attempt) {
  const double doublings = static_cast<double>(std::clamp<long>(attempt - 1, 0, 60));
  return std::min(options.reopen_delay_s * std::exp2(doublings), options.reopen_max_delay_s);
}

namespace internal {

void SleepUntil(Clock::time_point when, const Shared& shared) {
  while (!shared.Stopping()) {
    const Clock::time_point now = Clock::now();
    if (now >= when) return;
    std::this_thread::sleep_for(
        std::min<Clock::duration>(when - now, std::chrono::milliseconds(20)));
  }
}

namespace {

std::unique_ptr<FrameSource> Open(const std::string& spec, const Shared& shared) {
  if (shared.hooks.open_source) return shared.hooks.open_source(spec, shared.options.source);
  return OpenFrameSource(spec, shared.options.source);
}

void Put(const SourceFrame& frame, int64_t number, Clock::time_point delivered, Mailbox& box) {
  std::lock_guard lock(box.mutex);
  if (box.full) ++box.dropped;
  CopyToImage(frame, &box.image);
  box.capture_time_s = frame.capture_time_s;
  box.index = number;
  box.delivered_at = delivered;
  box.put_at = Clock::now();
  box.full = true;
  ++box.received;
  box.ready.notify_one();
}

// One camera's capture: frames in, faults handled. `who` names the camera in messages.
class Capture {
 public:
  Capture(const std::string& spec, uint32_t camera_id, Mailbox& box, Shared& shared)
      : spec_(spec),
        who_("camera " + std::to_string(camera_id) + " (" + spec + ")"),
        box_(box),
        shared_(shared) {}

  void Run() {
    source_ = Open(spec_, shared_);  // bad input at the start stops the run (InputError)
    start_ = Clock::now();
    SourceFrame frame;
    for (long n = 0; !shared_.Stopping();) {
      if (shared_.options.max_frames > 0 && n >= shared_.options.max_frames) break;
      if (!source_ && !Reopen()) continue;
      bool got = false;
      try {
        got = source_->Next(&frame);
      } catch (const CorruptFrameError& e) {
        Skipped(e.what());
        continue;
      } catch (const SourceError& e) {
        if (!e.reopenable()) {
          shared_.Report(who_ + ": " + e.what() + "; the source ends here");
          break;
        }
        Failed(e.what());
        continue;
      }
      if (!got) break;
      failures_ = 0;
      Deliver(frame);
      ++n;
    }
  }

 private:
  void Skipped(const std::string& what) {
    {
      std::lock_guard lock(box_.mutex);
      ++box_.skipped;
    }
    shared_.Report(who_ + ": " + what);
  }

  // The source failed: close it and wait the back-off before the next attempt to reopen it.
  void Failed(const std::string& what) {
    source_.reset();
    ++failures_;
    const long limit = shared_.options.reopen_attempts;
    if (limit > 0 && failures_ > limit) {
      throw EnvironmentError(who_ + ": " + what + "; gave up after " + std::to_string(limit) +
                             " attempts to reopen it");
    }
    const double delay_s = ReopenDelaySeconds(shared_.options, failures_);
    shared_.Report(who_ + ": " + what + "; reopening in " + FormatNumber(delay_s) + " s (attempt " +
                   std::to_string(failures_) + ")");
    SleepUntil(Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(delay_s)),
               shared_);
  }

  // Opens the source again; false (after the back-off) when it cannot be opened yet.
  bool Reopen() {
    {
      std::lock_guard lock(box_.mutex);
      ++box_.reopens;
    }
    try {
      source_ = Open(spec_, shared_);
    } catch (const InputError& e) {
      Failed(e.what());
      return false;
    }
    shared_.Report(who_ + ": reopened");
    base_ = next_number_;  // frame numbers go on where the failed source stopped
    start_ = Clock::now();
    return true;
  }

  void Deliver(const SourceFrame& frame) {
    // Under --rate native a file's frame is read ahead of its time and waits for it here: its
    // end-to-end latency starts when it is due, as a camera's frame would arrive then.
    if (shared_.options.rate == LiveRate::kNative) {
      SleepUntil(start_ + std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(frame.media_time_s)),
                 shared_);
    }
    const int64_t number = base_ + frame.index;
    next_number_ = number + 1;
    Put(frame, number, Clock::now(), box_);
  }

  const std::string& spec_;
  const std::string who_;
  Mailbox& box_;
  Shared& shared_;
  std::unique_ptr<FrameSource> source_;
  Clock::time_point start_;
  long failures_ = 0;  // consecutive failures without a frame delivered in between
  int64_t base_ = 0, next_number_ = 0;
};

}  // namespace

void CaptureThread(const std::string& spec, uint32_t camera_id, Mailbox& box, Shared& shared) {
  try {
    Capture(spec, camera_id, box, shared).Run();
  } catch (...) {
    shared.Fail();
  }
  std::lock_guard lock(box.mutex);
  box.closed = true;
  box.ready.notify_one();
}

}  // namespace internal
}  // namespace patlab::live

// The live loop (live/live_loop.h) with sources and a sender that fail on purpose, and a slow
// detection stage: a corrupt frame is skipped and counted, a failed source reopened with the
// documented back-off (and given up after reopen_attempts), a file's read error ends it, a
// refused packet is tried again, and a slow detector makes the mailbox drop the older frames
// (the newest wins; received = processed + dropped). No test depends on timing: the source and
// the detection stage wait for each other where an order matters.
#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/live/live_loop.h"
#include "patlab/live/udp_sender.h"
#include "patlab/vision/frame_io.h"

namespace patlab::live {
namespace {

using patlab::testing::kGoldenFrame;

LiveCamera Camera() {  // balls only: the loop's behaviour, not the detector's, is under test
  LiveCamera camera;
  camera.source = "fake";
  camera.thresholds = formats::LoadThresholds(kGoldenFrame + "thresholds.toml");
  camera.calibration = formats::LoadCalibration(kGoldenFrame + "calibration.toml");
  return camera;
}

// Frames taken by the detection thread; a source may wait for them (no drop can happen then).
struct Lockstep {
  std::mutex mutex;
  std::condition_variable changed;
  long taken = 0;
  long delivered = 0;  // by every source opened in the run
  void Took(int64_t frame) {
    std::lock_guard lock(mutex);
    ++taken;
    changed.notify_all();
    (void)frame;
  }
  void WaitTaken(long n) {
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return taken >= n; });
  }
};

// What a scripted source does on each call of Next, across every time it is opened.
enum class Step { kFrame, kCorrupt, kGone, kReadError, kCannotOpen, kEnd };

class ScriptedSource : public FrameSource {
 public:
  ScriptedSource(std::vector<Step>* script, size_t* next, Lockstep* lockstep)
      : script_(script),
        next_(next),
        lockstep_(lockstep),
        image_(vision::ReadFrame(kGoldenFrame + "png")) {}
  bool Next(SourceFrame* frame) override {
    const Step step = *next_ < script_->size() ? (*script_)[(*next_)++] : Step::kEnd;
    switch (step) {
      case Step::kCorrupt:
        throw CorruptFrameError("fake: frame skipped: bad bytes");
      case Step::kGone:
        throw SourceError("fake: device gone", true);
      case Step::kReadError:
        throw SourceError("fake: read failed", false);
      case Step::kEnd:
      case Step::kCannotOpen:
        return false;
      case Step::kFrame:
        break;
    }
    if (lockstep_) lockstep_->WaitTaken(lockstep_->delivered++);  // the previous one was taken
    frame->data = image_.data.data();
    frame->width_px = image_.width_px;
    frame->height_px = image_.height_px;
    frame->stride_bytes = image_.RowBytes();
    frame->format = image_.format;
    frame->index = delivered_++;
    return true;
  }
  const std::string& name() const override { return name_; }

 private:
  std::vector<Step>* script_;
  size_t* next_;
  Lockstep* lockstep_;
  camera::Image image_;
  int64_t delivered_ = 0;
  std::string name_ = "fake";
};

// A run of the scripted source: each open takes a kCannotOpen step as a failure to open.
struct ScriptedRun {
  std::vector<Step> script;
  size_t next = 0;
  Lockstep lockstep;
  bool use_lockstep = true;
  std::vector<std::string> messages;
  std::vector<uint32_t> frame_numbers;  // of the JSON lines
  LiveOptions options;
  LiveHooks hooks;
  LiveOutputs outputs;

  explicit ScriptedRun(std::vector<Step> s) : script(std::move(s)) {
    options.rate = LiveRate::kMax;
    options.reopen_delay_s = 0.001;
    options.reopen_max_delay_s = 0.004;
    hooks.open_source = [this](const std::string&, const FrameSourceOptions&) {
      if (next < script.size() && script[next] == Step::kCannotOpen) {
        ++next;
        throw InputError("fake: cannot open");
      }
      return std::make_unique<ScriptedSource>(&script, &next, use_lockstep ? &lockstep : nullptr);
    };
    hooks.before_detect = [this](uint32_t, int64_t frame) { lockstep.Took(frame); };
    outputs.message = [this](std::string_view m) { messages.emplace_back(m); };
    outputs.jsonl = [this](std::string_view line) {
      const size_t at = line.find("\"frame_number\":") + 15;
      frame_numbers.push_back(static_cast<uint32_t>(std::stoul(std::string(line.substr(at)))));
    };
  }
  LiveStats Run() {
    std::atomic<bool> stop{false};
    return RunLive({Camera()}, options, outputs, stop, hooks);
  }
};

TEST(LiveFaults, CorruptFramesAreSkippedAndCounted) {
  ScriptedRun run({Step::kFrame, Step::kCorrupt, Step::kFrame, Step::kCorrupt, Step::kCorrupt,
                   Step::kFrame, Step::kEnd});
  const LiveStats stats = run.Run();
  EXPECT_EQ(stats.received, 3);
  EXPECT_EQ(stats.skipped, 3);
  EXPECT_EQ(stats.processed, 3);
  EXPECT_EQ(stats.dropped, 0);
  EXPECT_EQ(stats.reopens, 0);
  EXPECT_EQ(run.frame_numbers, (std::vector<uint32_t>{0, 1, 2}));
  ASSERT_EQ(run.messages.size(), 3u);
  EXPECT_EQ(run.messages[0], "camera 0 (fake): fake: frame skipped: bad bytes");
}

TEST(LiveFaults, FailedSourceIsReopenedWithBackOff) {
  // Opened, two frames, gone; the first reopen cannot open it; the second can: one more frame.
  ScriptedRun run(
      {Step::kFrame, Step::kFrame, Step::kGone, Step::kCannotOpen, Step::kFrame, Step::kEnd});
  const LiveStats stats = run.Run();
  EXPECT_EQ(stats.received, 3);
  EXPECT_EQ(stats.processed, 3);
  EXPECT_EQ(stats.reopens, 2);
  EXPECT_EQ(run.frame_numbers, (std::vector<uint32_t>{0, 1, 2}));  // numbers go on after a reopen
  EXPECT_EQ(run.messages,
            (std::vector<std::string>{
                "camera 0 (fake): fake: device gone; reopening in 0.001 s (attempt 1)",
                "camera 0 (fake): fake: cannot open; reopening in 0.002 s (attempt 2)",
                "camera 0 (fake): reopened"}));
}

TEST(LiveFaults, GivesUpAfterReopenAttempts) {
  ScriptedRun run({Step::kFrame, Step::kGone, Step::kCannotOpen, Step::kCannotOpen, Step::kFrame});
  run.options.reopen_attempts = 2;
  EXPECT_INPUT_ERROR(run.Run(),
                     "camera 0 (fake): fake: cannot open; gave up after 2 attempts to reopen it");
}

TEST(LiveFaults, FileReadErrorEndsTheSource) {
  ScriptedRun run({Step::kFrame, Step::kReadError, Step::kFrame});
  const LiveStats stats = run.Run();
  EXPECT_EQ(stats.received, 1);
  EXPECT_EQ(stats.reopens, 0);
  EXPECT_EQ(run.messages,
            (std::vector<std::string>{"camera 0 (fake): fake: read failed; the source ends here"}));
}

TEST(LiveFaults, ReopenDelayDoublesUpToItsBound) {
  LiveOptions options;  // 0.1 s doubling, at most 5 s
  const std::vector<double> expected = {0.1, 0.2, 0.4, 0.8, 1.6, 3.2, 5.0, 5.0};
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_DOUBLE_EQ(ReopenDelaySeconds(options, static_cast<long>(i) + 1), expected[i]);
  }
  EXPECT_EQ(ReopenDelaySeconds(options, 1000), 5.0);
  options.reopen_max_delay_s = 0.05;
  EXPECT_INPUT_ERROR(Validate(options), "reopen_max_delay_s is 0.05; expected >= reopen_delay_s");
}

// A sender to 127.0.0.1 that refuses its first `refusals` datagrams.
class RefusingSender : public UdpSender {
 public:
  explicit RefusingSender(int refusals)
      : UdpSender(ParseUdpAddress("127.0.0.1:9", "--send"), {}), refusals_(refusals) {}
  bool Send(std::span<const uint8_t> bytes) override {
    ++calls_;
    if (calls_ <= refusals_) {
      SetLastError("refused by the test");
      return false;
    }
    (void)bytes;  // taken: nothing needs to reach the port
    return true;
  }

 private:
  int refusals_;
  int calls_ = 0;
};

TEST(LiveFaults, RefusedPacketIsTriedAgain) {
  ScriptedRun run({Step::kFrame, Step::kFrame, Step::kFrame, Step::kEnd});
  RefusingSender sender(4);  // packet 0: refused 3 times (not sent); packet 1: sent on its 2nd
  run.outputs.sender = &sender;
  const LiveStats stats = run.Run();
  EXPECT_EQ(stats.packets, 3);
  EXPECT_EQ(stats.send_failures, 1);
  EXPECT_EQ(stats.send_retries, 3);
  EXPECT_EQ(run.messages,
            (std::vector<std::string>{
                "sending to 127.0.0.1:9 failed: refused by the test; tried 3 times, the packet "
                "is counted as not sent and the next ones are tried",
                "sending to 127.0.0.1:9 works again"}));
}

// The detection stage is held on the first frame until the source has delivered all of them:
// the mailbox keeps only the newest, so frame 0 and the last frame are detected, the rest are
// dropped, and received = processed + dropped.
TEST(LiveFaults, SlowDetectionDropsOlderFramesNewestWins) {
  constexpr int kFrames = 10;
  std::vector<Step> script(kFrames, Step::kFrame);
  script.push_back(Step::kEnd);
  ScriptedRun run(script);
  run.use_lockstep = false;
  std::mutex mutex;
  std::condition_variable changed;
  bool detecting = false, all_delivered = false;
  const auto open = run.hooks.open_source;
  run.hooks.open_source = [&, open](const std::string& spec, const FrameSourceOptions& o) {
    // Frame 1 waits until the detection thread holds frame 0; the end of the script (the source
    // is asked past its last frame, so every frame is in the mailbox) releases the detector.
    class Gated : public FrameSource {
     public:
      Gated(std::unique_ptr<FrameSource> inner, std::function<void(int64_t)> before)
          : inner_(std::move(inner)), before_(std::move(before)) {}
      bool Next(SourceFrame* f) override {
        before_(calls_++);
        return inner_->Next(f);
      }
      const std::string& name() const override { return inner_->name(); }

     private:
      std::unique_ptr<FrameSource> inner_;
      std::function<void(int64_t)> before_;
      int64_t calls_ = 0;
    };
    return std::make_unique<Gated>(open(spec, o), [&](int64_t call) {
      std::unique_lock lock(mutex);
      if (call == 1) changed.wait(lock, [&] { return detecting; });
      if (call == kFrames) {
        all_delivered = true;
        changed.notify_all();
      }
    });
  };
  std::vector<int64_t> detected;
  run.hooks.before_detect = [&](uint32_t, int64_t frame) {
    detected.push_back(frame);
    std::unique_lock lock(mutex);
    detecting = true;
    changed.notify_all();
    changed.wait(lock, [&] { return all_delivered; });
  };
  const LiveStats stats = run.Run();
  EXPECT_EQ(stats.received, kFrames);
  EXPECT_EQ(stats.processed, 2);
  EXPECT_EQ(stats.dropped, kFrames - 2);
  EXPECT_EQ(stats.received, stats.processed + stats.dropped);
  EXPECT_EQ(detected, (std::vector<int64_t>{0, kFrames - 1}));
  EXPECT_EQ(run.frame_numbers, (std::vector<uint32_t>{0, kFrames - 1}));
}

}  // namespace
}  // namespace patlab::live

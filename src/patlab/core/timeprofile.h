// Stage timing of a pipeline, one mechanism for every pipeline (docs/architecture.md rule 8;
// apriltag common/timeprofile.h). A pipeline stamps the end of each numbered stage:
//
//   TimeProfile profile(/*enabled=*/options.collect_timing);
//   profile.Start();
//   ...stage 1...   profile.Stamp("1 candidates");
//   ...stage 2...   profile.Stamp("2 neighbours");
//
// and callers add profiles of many frames with +=, then print entries() in stage order. When not
// enabled a Stamp is one predictable branch: no clock is read.
#pragma once

#include <chrono>
#include <string_view>
#include <vector>

namespace patlab {

class TimeProfile {
 public:
  struct Entry {
    std::string_view stage;  // a string literal: "<number> <name>", as the header numbers it
    double seconds = 0.0;    // summed over every stamp of that stage
    long count = 0;          // how many stamps (frames, usually)
  };

  explicit TimeProfile(bool enabled = false) : enabled_(enabled) {}

  bool enabled() const { return enabled_; }
  void Start() {
    if (enabled_) last_ = Clock::now();
  }
  // Attributes the time since the last Start or Stamp to `stage` (a string literal).
  void Stamp(std::string_view stage) {
    if (!enabled_) return;
    const auto now = Clock::now();
    Add(stage, std::chrono::duration<double>(now - last_).count(), 1);
    last_ = now;
  }
  // Adds `seconds` to `stage` directly (for stages timed elsewhere, e.g. a decoder).
  void Add(std::string_view stage, double seconds, long count = 1);
  // Sums another profile, stage by stage; stages new to this one are appended in their order.
  TimeProfile& operator+=(const TimeProfile& other);

  const std::vector<Entry>& entries() const { return entries_; }
  double total_seconds() const;
  void Clear() { entries_.clear(); }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_ = false;
  Clock::time_point last_{};
  std::vector<Entry> entries_;
};

// Wall seconds since `start` on the steady clock: for run totals that are not pipeline stages.
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace patlab

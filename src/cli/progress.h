// The one progress reporter of the tool: done/total, rate, elapsed time and ETA on stderr, for
// every command that can run longer than a second; it starts after the first second, so a short
// run prints nothing. On a terminal the line is redrawn in place; otherwise (a log file, a pipe,
// CI) one line is printed per 10% so logs stay short. Off with -q. PATLAB_PROGRESS=always in the
// environment skips the quiet first second, so that short runs (tests, logs) report too.
// The library knows nothing of it: runners take a std::function<void(int, int)> callback.
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

namespace patlab::cli {

class Progress {
 public:
  static constexpr double kQuietSeconds = 1.0;  // nothing is shown before (unless forced)

  // `command` names the line ("patlab simulate"), `unit` what is counted ("points").
  // `enabled` false: silent. `terminal` says whether to redraw in place (IsTerminal()).
  Progress(std::string command, std::string unit, bool enabled, bool terminal,
           std::FILE* out = stderr);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // The callback for a library runner; empty when disabled, so the runner does no work for it.
  std::function<void(int, int)> Callback();
  // One report: `done` of `total` units are done.
  void Update(int done, int total);

  // The line for a state of the run, e.g. "patlab track: 12/40 blocks, 3.1 blocks/s, 4 s
  // elapsed, ETA 9 s" (exposed for the tests).
  std::string Line(int done, int total, double elapsed_s) const;

 private:
  std::string command_, unit_;
  bool enabled_, terminal_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_;
  int last_decile_ = -1;
  bool line_open_ = false;
  bool started_ = false;
  bool always_ = false;  // PATLAB_PROGRESS=always: no quiet first second
};

// Whether stderr is a terminal.
bool StderrIsTerminal();

}  // namespace patlab::cli

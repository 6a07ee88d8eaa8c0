#include "cli/progress.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include "patlab/core/format.h"

namespace patlab::cli {

namespace {

// "4 s", "2 min 05 s", "1 h 02 min": durations for people.
std::string Duration(double seconds) {
  if (!(seconds >= 0.0) || seconds > 1e7) return "?";
  const long s = static_cast<long>(seconds + 0.5);
  if (s < 60) return StringPrintf("%ld s", s);
  if (s < 3600) return StringPrintf("%ld min %02ld s", s / 60, s % 60);
  return StringPrintf("%ld h %02ld min", s / 3600, (s % 3600) / 60);
}

}  // namespace

bool StderrIsTerminal() { return ::isatty(STDERR_FILENO) != 0; }

Progress::Progress(std::string command, std::string unit, bool enabled, bool terminal,
                   std::FILE* out)
    : command_(std::move(command)),
      unit_(std::move(unit)),
      enabled_(enabled),
      terminal_(terminal),
      out_(out),
      start_(std::chrono::steady_clock::now()) {
  const char* mode = std::getenv("PATLAB_PROGRESS");
  always_ = mode != nullptr && std::strcmp(mode, "always") == 0;
}

std::function<void(int, int)> Progress::Callback() {
  if (!enabled_) return {};
  return [this](int done, int total) { Update(done, total); };
}

std::string Progress::Line(int done, int total, double elapsed_s) const {
  std::string line =
      command_ + ": " + std::to_string(done) + "/" + std::to_string(total) + " " + unit_;
  if (total > 0) line += StringPrintf(" (%d%%)", static_cast<int>(100.0 * done / total));
  const double rate = elapsed_s > 0.0 ? done / elapsed_s : 0.0;
  line +=
      ", " + FormatSignificant(rate, 3) + " " + unit_ + "/s, " + Duration(elapsed_s) + " elapsed";
  if (done < total) {
    line += ", ETA " + (rate > 0.0 ? Duration((total - done) / rate) : std::string("?"));
  }
  return line;
}

void Progress::Update(int done, int total) {
  if (!enabled_) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // A run shorter than a second says nothing; a longer one starts reporting after that second.
  if (!started_ && elapsed < kQuietSeconds && !always_) return;
  started_ = true;
  if (terminal_) {
    // \033[K clears what a longer previous line left behind.
    std::fprintf(out_, "\r%s\033[K", Line(done, total, elapsed).c_str());
    line_open_ = done < total;
    if (!line_open_) std::fputc('\n', out_);
    std::fflush(out_);
    return;
  }
  const int decile = total > 0 ? static_cast<int>(10LL * done / total) : 10;
  if (decile == last_decile_) return;
  last_decile_ = decile;
  std::fprintf(out_, "%s\n", Line(done, total, elapsed).c_str());
  std::fflush(out_);
}

}  // namespace patlab::cli

// What dead writers left (atomic_file.h, SweepDeadWriters): a journalled commit rolled forward,
// other temporaries and moved-aside copies of processes that no longer exist removed.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>

#include "patlab/io/atomic_file.h"
#include "patlab/io/atomic_file_internal.h"

namespace patlab::io {

namespace atomic_detail {

namespace fs = std::filesystem;

std::string Sibling(const std::string& path, const char* tag, long pid) {
  const fs::path p(path);
  std::string name = ".";
  name += p.filename().string();
  name += tag;
  name += std::to_string(pid);
  return (p.parent_path() / name).string();
}

std::string JournalPath(const std::string& folder, long pid) {
  return (fs::path(folder) / (std::string(kJournalPrefix) + std::to_string(pid))).string();
}

std::vector<std::string> FoldersOf(const std::vector<std::string>& paths) {
  std::vector<std::string> folders;
  for (const std::string& path : paths) {
    fs::path folder = fs::path(path).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    const fs::path absolute = fs::absolute(folder, ec).lexically_normal();
    const std::string text = ec ? folder.string() : absolute.string();
    if (std::find(folders.begin(), folders.end(), text) == folders.end()) folders.push_back(text);
  }
  return folders;
}

namespace {

// A file of patlab's own naming in a swept folder.
struct Leftover {
  enum Kind { kTemp, kOld, kJournal } kind;
  long pid;
  std::string path, target;
};

bool ParsePid(std::string_view digits, long* pid) {
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), *pid);
  return !digits.empty() && ec == std::errc() && end == digits.data() + digits.size() && *pid > 0;
}

std::optional<Leftover> Classify(const fs::path& folder, const std::string& name) {
  long pid = 0;
  const std::string_view journal(kJournalPrefix);
  if (name.starts_with(journal)) {
    if (!ParsePid(std::string_view(name).substr(journal.size()), &pid)) return std::nullopt;
    return Leftover{Leftover::kJournal, pid, (folder / name).string(), ""};
  }
  for (const auto& [tag, kind] :
       {std::pair{kTempTag, Leftover::kTemp}, {kOldTag, Leftover::kOld}}) {
    const size_t at = name.rfind(tag);
    if (name.front() != '.' || at == std::string::npos || at < 2) continue;
    if (!ParsePid(std::string_view(name).substr(at + std::string_view(tag).size()), &pid)) continue;
    return Leftover{kind, pid, (folder / name).string(),
                    (folder / name.substr(1, at - 1)).string()};
  }
  return std::nullopt;
}

// A process that no longer exists; this process and every process we may not signal live.
bool IsDead(long pid) {
  return pid != static_cast<long>(::getpid()) && ::kill(static_cast<pid_t>(pid), 0) != 0 &&
         errno == ESRCH;
}

std::vector<Leftover> DeadLeftovers(const std::string& folder) {
  std::vector<Leftover> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.front() != '.') continue;
    std::optional<Leftover> leftover = Classify(folder, name);
    if (leftover && IsDead(leftover->pid)) found.push_back(std::move(*leftover));
  }
  return found;
}

// The targets a journal lists, in commit order (manifest last); empty when it was cut short.
std::vector<std::string> ReadJournal(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  if (lines.empty() || lines.back() != kJournalEnd) return {};
  lines.pop_back();
  return lines;
}

// Finishes a dead writer's commit: every temporary still there moved into place, manifest last,
// then the old copies and the journals removed. Idempotent, so a sweep that dies half-way is
// finished by the next.
int RollForward(const Leftover& journal) {
  const std::vector<std::string> targets = ReadJournal(journal.path);
  int changed = 0;
  for (const std::string& target : targets) {
    const std::string temp = Sibling(target, kTempTag, journal.pid);
    if (Exists(temp) && ::rename(temp.c_str(), target.c_str()) == 0) ++changed;
  }
  for (const std::string& target : targets) {
    if (::unlink(Sibling(target, kOldTag, journal.pid).c_str()) == 0) ++changed;
  }
  for (const std::string& folder : FoldersOf(targets)) {
    const std::string other = JournalPath(folder, journal.pid);
    if (other != journal.path && ::unlink(other.c_str()) == 0) ++changed;
  }
  if (::unlink(journal.path.c_str()) == 0) ++changed;
  return changed;
}

// A temporary of a writer that died before its journal was complete never held a whole file;
// an old copy without a journal (none is made before the journal) goes back if its target is
// missing.
int RemoveUncommitted(const Leftover& leftover) {
  if (leftover.kind == Leftover::kOld && !Exists(leftover.target)) {
    return ::rename(leftover.path.c_str(), leftover.target.c_str()) == 0 ? 1 : 0;
  }
  return ::unlink(leftover.path.c_str()) == 0 ? 1 : 0;
}

}  // namespace

void SweepOnce(const std::vector<std::string>& folders) {
  static std::mutex mutex;
  static std::set<std::string> swept;
  for (const std::string& folder : folders) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      if (!swept.insert(folder).second) continue;
    }
    SweepDeadWriters(folder);
  }
}

}  // namespace atomic_detail

int SweepDeadWriters(const std::string& folder) {
  using atomic_detail::Leftover;
  int changed = 0;
  for (const Leftover& leftover : atomic_detail::DeadLeftovers(folder)) {
    if (leftover.kind == Leftover::kJournal) changed += atomic_detail::RollForward(leftover);
  }
  for (const Leftover& leftover : atomic_detail::DeadLeftovers(folder)) {
    if (leftover.kind != Leftover::kJournal) changed += atomic_detail::RemoveUncommitted(leftover);
  }
  return changed;
}

}  // namespace patlab::io

#include "patlab/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "patlab/core/error.h"
#include "patlab/io/atomic_file_internal.h"
#include "patlab/io/made_folders.h"
#include "patlab/io/name.h"

namespace patlab::io {

namespace {

namespace fs = std::filesystem;
using atomic_detail::Exists;
using atomic_detail::IsDirectory;
using atomic_detail::JournalPath;
using atomic_detail::kJournalEnd;
using atomic_detail::kOldTag;
using atomic_detail::kTempTag;
using atomic_detail::Sibling;

// What the signal handler may touch: only lock-free atomics and a null-terminated array of C
// strings that stays alive while it is published (async-signal-safe: unlink, signal, raise).
std::atomic<const char* const*> g_temp_paths{nullptr};
std::atomic<const MadeFolders*> g_made_folders{nullptr};
std::atomic<int> g_committing{0};
std::atomic<int> g_pending_signal{0};
static_assert(std::atomic<const char* const*>::is_always_lock_free);
static_assert(std::atomic<const MadeFolders*>::is_always_lock_free);
static_assert(std::atomic<int>::is_always_lock_free);

void RemoveTemps(const char* const* paths) {
  if (paths == nullptr) return;
  for (const char* const* p = paths; *p != nullptr; ++p) ::unlink(*p);
}

extern "C" void OnTerminatingSignal(int signal_number) {
  if (g_committing.load() != 0) {
    g_pending_signal.store(signal_number);
    return;
  }
  RemoveTemps(g_temp_paths.load());
  if (const MadeFolders* made = g_made_folders.load(); made != nullptr) made->RemoveMade();
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

[[noreturn]] void Fail(const std::string& path, const std::string& reason) {
  throw EnvironmentError(EscapeForMessage(path, 1024) + ": cannot write: " + reason +
                         "; expected a writable location");
}

// The file descriptor of a temporary being written, closed and removed unless Finish succeeds.
class TempFile {
 public:
  TempFile(const std::string& path, const std::string& temp) : path_(path), temp_(temp) {
    fd_ = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) Fail(path, std::strerror(errno));
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd_ < 0) return;
    ::close(fd_);
    ::unlink(temp_.c_str());
  }

  void Write(std::string_view content) {
    size_t done = 0;
    while (done < content.size()) {
      const ssize_t n = ::write(fd_, content.data() + done, content.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) Fail(path_, std::strerror(n < 0 ? errno : ENOSPC));
      done += static_cast<size_t>(n);
    }
  }

  void Finish() {
    const bool ok = ::fsync(fd_) == 0;
    const int saved_errno = errno;
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0 || !ok) {
      ::unlink(temp_.c_str());
      Fail(path_, std::strerror(ok ? errno : saved_errno));
    }
  }

 private:
  const std::string& path_;
  const std::string& temp_;
  int fd_ = -1;
};

// One target's commit state, for the rollback.
struct Slot {
  std::string target, temp, backup;
  bool backed_up = false, placed = false;
};

// Undoes the renames done so far, newest first: the new file goes, the old one comes back.
void RollBack(std::vector<Slot>* slots) {
  for (auto it = slots->rbegin(); it != slots->rend(); ++it) {
    if (it->placed) ::unlink(it->target.c_str());
    if (it->backed_up) ::rename(it->backup.c_str(), it->target.c_str());
    ::unlink(it->temp.c_str());
  }
}

// Moves an existing target aside, then the temporary into place. Returns errno, or 0.
int Place(Slot* s) {
  if (Exists(s->target)) {
    if (::rename(s->target.c_str(), s->backup.c_str()) != 0) return errno;
    s->backed_up = true;
  }
  if (::rename(s->temp.c_str(), s->target.c_str()) != 0) return errno;
  s->placed = true;
  return 0;
}

// The renames, the manifest (last slot) moved aside first and placed last.
void Commit(std::vector<Slot>* slots) {
  Slot& manifest = slots->back();
  int error = 0;
  std::string failed = manifest.target;
  if (Exists(manifest.target)) {
    if (::rename(manifest.target.c_str(), manifest.backup.c_str()) != 0) error = errno;
    manifest.backed_up = error == 0;
  }
  for (size_t k = 0; k + 1 < slots->size() && error == 0; ++k) {
    error = Place(&(*slots)[k]);
    failed = (*slots)[k].target;
  }
  if (error == 0) {
    if (::rename(manifest.temp.c_str(), manifest.target.c_str()) != 0) error = errno;
    manifest.placed = error == 0;
    failed = manifest.target;
  }
  if (error != 0) {
    RollBack(slots);
    Fail(failed, std::strerror(error));
  }
  for (const Slot& s : *slots) {
    if (s.backed_up) ::unlink(s.backup.c_str());
  }
}

void CreateParents(const std::string& path, MadeFolders* made) {
  const fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) return;
  if (const std::error_code ec = made->Make(parent.string())) Fail(path, ec.message());
}

// The folders of the result set's files.
std::vector<std::string> ParentsOf(const std::vector<std::string>& paths) {
  std::vector<std::string> parents;
  for (const std::string& path : paths) parents.push_back(fs::path(path).parent_path().string());
  return parents;
}

// Publishes the temporary paths and the folders made for them to the signal handler for the
// lifetime of this object.
class PublishedTemps {
 public:
  PublishedTemps(const std::vector<Slot>& slots, const MadeFolders* made) {
    for (const Slot& s : slots) pointers_.push_back(s.temp.c_str());
    pointers_.push_back(nullptr);
    g_temp_paths.store(pointers_.data());
    g_made_folders.store(made);
  }
  ~PublishedTemps() {
    g_made_folders.store(nullptr);
    g_temp_paths.store(nullptr);
  }
  PublishedTemps(const PublishedTemps&) = delete;
  PublishedTemps& operator=(const PublishedTemps&) = delete;

 private:
  std::vector<const char*> pointers_;
};

// Holds SIGINT/SIGTERM/SIGHUP back for the commit renames; re-raises one that came meanwhile.
class CommitGuard {
 public:
  CommitGuard() { g_committing.store(1); }
  ~CommitGuard() {
    g_committing.store(0);
    if (const int s = g_pending_signal.exchange(0); s != 0) std::raise(s);
  }
  CommitGuard(const CommitGuard&) = delete;
  CommitGuard& operator=(const CommitGuard&) = delete;
};

// The commit journals (atomic_file_internal.h): written and synced in every folder of the set
// before the first rename, removed when the commit is done or rolled back, so a writer killed
// between the two leaves a commit that the next writer's sweep rolls forward.
class Journals {
 public:
  explicit Journals(const std::vector<Slot>& slots) {
    std::vector<std::string> targets;
    std::string text;
    for (const Slot& s : slots) {
      targets.push_back(s.target);
      std::error_code ec;
      const fs::path absolute = fs::absolute(s.target, ec);
      text += (ec ? fs::path(s.target) : absolute).lexically_normal().string() + "\n";
    }
    text += kJournalEnd;
    text += "\n";
    try {
      for (const std::string& folder : atomic_detail::FoldersOf(targets)) {
        paths_.push_back(JournalPath(folder, ::getpid()));
        TempFile file(slots.back().target, paths_.back());
        file.Write(text);
        file.Finish();
      }
    } catch (...) {
      Remove();
      for (const Slot& s : slots) ::unlink(s.temp.c_str());
      throw;
    }
  }
  ~Journals() { Remove(); }
  Journals(const Journals&) = delete;
  Journals& operator=(const Journals&) = delete;

 private:
  void Remove() {
    for (const std::string& path : paths_) ::unlink(path.c_str());
  }

  std::vector<std::string> paths_;
};

}  // namespace

bool IsFileBaseName(std::string_view name) {
  static_assert(kMaxBaseNameBytes <= kMaxNameBytes);
  return name.size() <= kMaxBaseNameBytes && NameProblem(name).empty();
}

namespace {
// Two outputs of one result set with the same path would overwrite each other (a track
// experiment named "track_errors"): bad input, found before any work.
void CheckDistinct(const std::vector<std::string>& paths) {
  for (size_t k = 0; k < paths.size(); ++k) {
    for (size_t j = 0; j < k; ++j) {
      if (paths[j] == paths[k]) {
        throw InputError(EscapeForMessage(paths[k], 1024) +
                         ": named twice in one result set; expected distinct output files");
      }
    }
  }
}
}  // namespace

void CheckWritable(const std::vector<std::string>& paths) {
  CheckDistinct(paths);
  std::vector<std::string> existing;
  for (const std::string& folder : atomic_detail::FoldersOf(paths)) {
    if (IsDirectory(folder)) existing.push_back(folder);
  }
  atomic_detail::SweepOnce(existing);
  for (const std::string& path : paths) {
    if (IsDirectory(path)) Fail(path, "it is a directory");
    fs::path folder = fs::path(path).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    while (!fs::exists(folder, ec) && folder.has_parent_path() && folder != folder.parent_path()) {
      if (ec) break;
      folder = folder.parent_path();
    }
    if (ec) Fail(path, ec.message());
    // A relative folder none of whose components exists yet ("results/fig5.csv" in an empty
    // working directory) is created in the working directory.
    if (!fs::exists(folder, ec) && folder.is_relative()) folder = ".";
    if (!IsDirectory(folder.string())) Fail(path, folder.string() + " is not a directory");
    if (::access(folder.c_str(), W_OK | X_OK) != 0) Fail(path, std::strerror(errno));
  }
}

void WriteFilesAtomic(const std::vector<StreamedFile>& files) {
  if (files.empty()) return;
  std::vector<std::string> paths;
  for (const StreamedFile& file : files) paths.push_back(file.path);
  CheckDistinct(paths);
  atomic_detail::SweepOnce(atomic_detail::FoldersOf(paths));
  std::vector<Slot> slots;
  for (const StreamedFile& file : files) {
    if (IsDirectory(file.path)) Fail(file.path, "it is a directory");
    slots.push_back({file.path, Sibling(file.path, kTempTag, ::getpid()),
                     Sibling(file.path, kOldTag, ::getpid())});
  }
  // Folders made for the set are removed again, innermost first and only while empty, unless the
  // commit below succeeds (made_folders.h).
  MadeFolders made(ParentsOf(paths));
  const PublishedTemps published(slots, &made);
  try {
    for (size_t k = 0; k < files.size(); ++k) {
      CreateParents(files[k].path, &made);
      TempFile temp(files[k].path, slots[k].temp);
      files[k].produce([&temp](std::string_view text) { temp.Write(text); });
      temp.Finish();
    }
  } catch (...) {
    for (const Slot& s : slots) ::unlink(s.temp.c_str());
    throw;
  }
  const CommitGuard guard;
  const Journals journals(slots);
  Commit(&slots);
  made.Keep();
  g_made_folders.store(nullptr);  // a signal held back by the guard must not touch them
}

void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<StreamedFile> streamed;
  streamed.reserve(files.size());
  for (const auto& [path, content] : files) {
    streamed.push_back({path, [&content = content](const TextSink& sink) { sink(content); }});
  }
  WriteFilesAtomic(streamed);
}

void InstallSignalCleanup() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = OnTerminatingSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) {
      // A signal the parent chose to ignore (nohup, a background job) stays ignored.
      struct sigaction old {};
      if (::sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      ::sigaction(s, &action, nullptr);
    }
    return true;
  }();
  (void)installed;
}

std::vector<std::string> OutputNames(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  names.reserve(paths.size());
  for (const std::string& p : paths) names.push_back(fs::path(p).filename().string());
  return names;
}

namespace atomic_detail {

bool IsDirectory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool Exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

}  // namespace atomic_detail

}  // namespace patlab::io

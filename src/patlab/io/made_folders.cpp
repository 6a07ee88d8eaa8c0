#include "patlab/io/made_folders.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>

#include "patlab/io/atomic_file_internal.h"

namespace patlab::io {

namespace {

namespace fs = std::filesystem;
using atomic_detail::Exists;
using atomic_detail::IsDirectory;

static_assert(std::atomic<bool>::is_always_lock_free);

// `folder` as the plan spells it: lexically normal, no trailing separator.
fs::path Normal(const std::string& folder) {
  fs::path path = fs::path(folder).lexically_normal();
  if (!path.empty() && !path.has_filename() && path != path.root_path()) {
    path = path.parent_path();
  }
  return path;
}

// `inner` is `outer` or below it (lexically).
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

}  // namespace

MadeFolders::MadeFolders(const std::vector<std::string>& folders) {
  for (const std::string& folder : folders) {
    std::vector<std::string> missing;  // innermost first
    for (fs::path p = Normal(folder); !p.empty() && p != "." && !Exists(p); p = p.parent_path()) {
      missing.push_back(p.string());
      if (p == p.parent_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      if (std::find(planned_.begin(), planned_.end(), *it) == planned_.end()) {
        planned_.push_back(*it);
      }
    }
  }
  made_ = std::make_unique<std::atomic<bool>[]>(planned_.size());
  for (size_t k = 0; k < planned_.size(); ++k) made_[k].store(false);
}

MadeFolders::~MadeFolders() {
  if (!kept_) RemoveMade();
}

std::error_code MadeFolders::Make(const std::string& folder) {
  const fs::path target = Normal(folder);
  for (size_t k = 0; k < planned_.size(); ++k) {
    if (made_[k].load() || !IsWithin(target, planned_[k])) continue;
    if (::mkdir(planned_[k].c_str(), 0777) == 0) {
      made_[k].store(true);
    } else if (errno != EEXIST || !IsDirectory(planned_[k])) {
      return {errno == EEXIST ? ENOTDIR : errno, std::generic_category()};
    }
  }
  // A folder that existed when planned and is gone now is made again, but not as this object's.
  std::error_code ec;
  if (!target.empty() && !IsDirectory(target)) fs::create_directories(target, ec);
  return ec;
}

void MadeFolders::RemoveMade() const noexcept {
  for (size_t k = planned_.size(); k-- > 0;) {
    if (made_[k].load()) ::rmdir(planned_[k].c_str());
  }
}

std::vector<std::string> MadeFolders::Made() const {
  std::vector<std::string> made;
  for (size_t k = 0; k < planned_.size(); ++k) {
    if (made_[k].load()) made.push_back(planned_[k]);
  }
  return made;
}

}  // namespace patlab::io

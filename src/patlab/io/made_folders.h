// Output folders made like `mkdir -p` and removed again when what they were made for is not
// committed (docs/hardening.md, "Results all or nothing"): a command that fails before it commits
// its results leaves no empty folder behind. Only the folders this object made in this run are
// removed, only while still empty, innermost first; folders that existed, or that another process
// made meanwhile, are never touched. io/atomic_file.cpp makes every result folder through it, and
// its signal handler (InstallSignalCleanup) removes the made folders with the temporaries.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace patlab::io {

class MadeFolders {
 public:
  // Plans, making nothing: every folder of `folders` that does not exist now and its missing
  // parents, outermost first ("new/deep" in an empty folder: "new", then "new/deep").
  explicit MadeFolders(const std::vector<std::string>& folders);
  // Unless Keep() was called: RemoveMade().
  ~MadeFolders();
  MadeFolders(const MadeFolders&) = delete;
  MadeFolders& operator=(const MadeFolders&) = delete;

  // Makes `folder` (one of the planned folders' or below none of them: then nothing) with its
  // planned parents, outermost first. A folder that exists by now is not this object's. Returns
  // the error of the first mkdir that failed (`folder` exists as a file: ENOTDIR), or none.
  std::error_code Make(const std::string& folder);
  // What the folders were made for is committed: they stay.
  void Keep() { kept_ = true; }
  // Removes the folders this object made and that are still empty, innermost first. Only calls
  // rmdir, so a signal handler may call it.
  void RemoveMade() const noexcept;
  // The folders this object made, outermost first.
  std::vector<std::string> Made() const;

 private:
  std::vector<std::string> planned_;
  std::unique_ptr<std::atomic<bool>[]> made_;
  bool kept_ = false;
};

}  // namespace patlab::io

// Inside the atomic result files (atomic_file.h): the names of a writer's temporaries, moved-aside
// copies and commit journals, shared by the writer (atomic_file.cpp) and the sweep of what dead
// writers left (atomic_file_sweep.cpp).
#pragma once

#include <string>
#include <vector>

namespace patlab::io::atomic_detail {

// ".<name>.patlab-tmp.<pid>": a file of a result set being written.
inline constexpr const char* kTempTag = ".patlab-tmp.";
// ".<name>.patlab-old.<pid>": a target's old content, moved aside during the commit.
inline constexpr const char* kOldTag = ".patlab-old.";
// ".patlab-commit.<pid>": the journal of a commit in progress, one per folder written to.
inline constexpr const char* kJournalPrefix = ".patlab-commit.";
// The journal's last line: a journal without it was cut while being written, before any rename.
inline constexpr const char* kJournalEnd = "end";

// The sibling of `path` that process `pid` uses: "<folder>/.<name><tag><pid>".
std::string Sibling(const std::string& path, const char* tag, long pid);
// The journal of process `pid` in `folder`.
std::string JournalPath(const std::string& folder, long pid);
// The distinct folders of `paths`, absolute ("." for a bare name).
std::vector<std::string> FoldersOf(const std::vector<std::string>& paths);
// stat(2): `path` is a directory (or a link to one). lstat(2): something is at `path`.
bool IsDirectory(const std::string& path);
bool Exists(const std::string& path);
// SweepDeadWriters on each folder not yet swept by this process.
void SweepOnce(const std::vector<std::string>& folders);

}  // namespace patlab::io::atomic_detail

// Results are written all or nothing (docs/hardening.md, "Results all or nothing"). The files of
// one result set are first written in full to hidden temporary files beside their targets
// (".<name>.patlab-tmp.<pid>"), flushed and synced; then they are committed by renames, the
// LAST file of the list (the manifest) last, after any old manifest has been moved aside. So at
// every instant the target directory holds either the old result set with its old manifest, or
// no manifest (a commit in progress or interrupted by SIGKILL or a power cut), or the new set
// with its new manifest: readers trust a result set only when its manifest is there. A rename
// that fails rolls every target back to its old content. SIGINT, SIGTERM and SIGHUP are held
// back during the renames and delivered after them, and remove the temporary files when they
// arrive while the files are being written (InstallSignalCleanup); any other failure removes them
// before the exception leaves WriteFilesAtomic.
//
// SIGKILL and power cuts cannot be caught, so the next write into the same folder finishes what
// a dead writer left (SweepDeadWriters): before its first rename a writer records its targets in
// a commit journal ".patlab-commit.<pid>" in each folder it writes to, removed once the commit is
// done. A dead writer's temporaries without a journal were never complete and are removed; with
// a journal they are complete (written and synced before the journal), so the commit is rolled
// forward: the new set is placed, manifest last, and the moved-aside old copies are removed.
// A writer is dead when kill(pid, 0) fails with ESRCH; files of a live process (or of this one)
// are never touched.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace patlab::io {

// Writes several files as one result set (see above), creating missing parent directories like
// `mkdir -p` (removed again, innermost first and only while empty, when the set is not committed:
// an exception, or a signal the handler of InstallSignalCleanup sees; made_folders.h); the
// last file is the manifest and is committed last. Throws EnvironmentError
// ("<path>: cannot write: <reason>; expected a writable location") on failure, with every target
// as it was before the call and no temporary file left.
void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files);

// A file of a result set whose content is produced piece by piece instead of held in memory
// whole (35 MB of per-sample errors for `patlab analyze` on a million samples): `produce` is
// called once with a sink; each call of the sink appends its text to the file's temporary. The
// text is the concatenation of the pieces, in order. An exception from `produce` or from the sink
// (EnvironmentError when the write fails) removes every temporary and leaves the targets as they
// were, as for the string form above.
using TextSink = std::function<void(std::string_view)>;
struct StreamedFile {
  std::string path;
  std::function<void(const TextSink&)> produce;
};
void WriteFilesAtomic(const std::vector<StreamedFile>& files);

// Checks, before a long run, that WriteFilesAtomic could write `paths`: no target is a
// directory, and the nearest existing ancestor of each target's folder is a writable,
// searchable directory. Creates nothing. Throws EnvironmentError with the same message shape.
void CheckWritable(const std::vector<std::string>& paths);

// True when `name` can be the base of an output file inside a chosen directory: a name by
// io/name.h's rule (NameProblem), so `--name ../../x` cannot leave the output directory; at most
// kMaxBaseNameBytes bytes, so the temporary ".<name>.<ext>.patlab-tmp.<pid>" fits in 255.
inline constexpr size_t kMaxBaseNameBytes = 200;
bool IsFileBaseName(std::string_view name);
// The expectation messages quote for a bad base name.
inline constexpr const char* kFileBaseNameExpected =
    "a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control "
    "characters or NUL";

// The names of the files of a result set, without their folder, as its manifest lists them: a
// manifest describes results, so it reads the same wherever they were written.
std::vector<std::string> OutputNames(const std::vector<std::string>& paths);

// Finishes or removes what dead writers left in `folder` (see above): rolls a journalled commit
// forward and removes the other temporaries and moved-aside copies of processes that no longer
// exist. Only names of patlab's own form are touched. A missing folder is not an error. Returns
// the number of files removed or renamed. WriteFilesAtomic and CheckWritable call it for each
// folder they write to, once per folder and process.
int SweepDeadWriters(const std::string& folder);

// Installs the SIGINT / SIGTERM / SIGHUP handler that removes WriteFilesAtomic's temporary files
// when a signal arrives while they are written, and defers a signal that arrives during the
// commit renames until they are done; the signal then takes its default action (the process
// ends). Called once by the CLI's main; idempotent. A library user who installs its own handlers
// may skip it: failures other than signals clean up without it.
void InstallSignalCleanup();

}  // namespace patlab::io

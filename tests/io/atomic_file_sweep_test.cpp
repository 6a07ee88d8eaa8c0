// SweepDeadWriters (io/atomic_file.h): what a writer killed by SIGKILL left in a folder.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "../test_util.h"
#include "patlab/io/atomic_file.h"

namespace patlab::io {
namespace {

namespace fs = std::filesystem;
using testing::FileNames;
using testing::ReadFile;
using testing::TempDir;

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The pid of a process that has exited and been reaped.
std::string DeadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return std::to_string(child);
}

TEST(SweepDeadWriters, RemovesTemporariesOfDeadWritersOnly) {
  TempDir dir;
  const std::string dead = DeadPid(), live = std::to_string(::getpid());
  Write(dir.Path("a.csv"), "old a");
  Write(dir.Path(".a.csv.patlab-tmp." + dead), "half");
  Write(dir.Path(".a.json.patlab-tmp." + dead), "");
  Write(dir.Path(".a.csv.patlab-tmp." + live), "being written");
  Write(dir.Path(".a.csv.patlab-tmp.12x"), "not patlab's");
  Write(dir.Path("a.csv.patlab-tmp." + dead), "not hidden");
  EXPECT_EQ(SweepDeadWriters(dir.Path("")), 2);
  EXPECT_EQ(FileNames(dir.Path("")),
            (std::set<std::string>{"a.csv", ".a.csv.patlab-tmp." + live, ".a.csv.patlab-tmp.12x",
                                   "a.csv.patlab-tmp." + dead}));
  EXPECT_EQ(ReadFile(dir.Path("a.csv")), "old a");
}

// Killed between two renames: a.csv already new, the old manifest aside, the new one still a
// temporary. The journal says the temporaries were complete: the commit is finished.
TEST(SweepDeadWriters, RollsAJournalledCommitForward) {
  TempDir dir;
  const std::string dead = DeadPid();
  const std::string a = dir.Path("a.csv"), m = dir.Path("a.json");
  Write(a, "new a");
  Write(dir.Path(".a.csv.patlab-old." + dead), "old a");
  Write(dir.Path(".a.json.patlab-old." + dead), "old m");
  Write(dir.Path(".a.json.patlab-tmp." + dead), "new m");
  Write(dir.Path(".patlab-commit." + dead), a + "\n" + m + "\nend\n");
  EXPECT_EQ(SweepDeadWriters(dir.Path("")), 4);
  EXPECT_EQ(FileNames(dir.Path("")), (std::set<std::string>{"a.csv", "a.json"}));
  EXPECT_EQ(ReadFile(a), "new a");
  EXPECT_EQ(ReadFile(m), "new m");
}

// A journal cut short was being written, so no rename had happened: the old set stays.
TEST(SweepDeadWriters, KeepsTheOldSetWhenTheJournalIsIncomplete) {
  TempDir dir;
  const std::string dead = DeadPid();
  const std::string a = dir.Path("a.csv"), m = dir.Path("a.json");
  Write(a, "old a");
  Write(m, "old m");
  Write(dir.Path(".a.csv.patlab-tmp." + dead), "new a");
  Write(dir.Path(".a.json.patlab-tmp." + dead), "new m");
  Write(dir.Path(".patlab-commit." + dead), a + "\n" + m.substr(0, 5));
  EXPECT_EQ(SweepDeadWriters(dir.Path("")), 3);
  EXPECT_EQ(FileNames(dir.Path("")), (std::set<std::string>{"a.csv", "a.json"}));
  EXPECT_EQ(ReadFile(a), "old a");
  EXPECT_EQ(ReadFile(m), "old m");
}

TEST(SweepDeadWriters, TheNextWriteIntoTheFolderSweeps) {
  TempDir dir;
  const std::string dead = DeadPid();
  fs::create_directories(dir.Path("out"));
  Write(dir.Path("out/.b.csv.patlab-tmp." + dead), "half");
  WriteFilesAtomic({{dir.Path("out/a.csv"), "a"}, {dir.Path("out/a.json"), "m"}});
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.csv", "a.json"}));
}

TEST(SweepDeadWriters, AMissingFolderIsNothingToSweep) {
  TempDir dir;
  EXPECT_EQ(SweepDeadWriters(dir.Path("none")), 0);
}

}  // namespace
}  // namespace patlab::io

#include "patlab/io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <vector>

#include "../test_util.h"

namespace patlab::io {
namespace {

namespace fs = std::filesystem;
using testing::FileNames;
using testing::ReadFile;
using testing::TempDir;

TEST(AtomicFile, WritesEveryFileAndLeavesNoTemporary) {
  TempDir dir;
  WriteFilesAtomic({{dir.Path("out/a.csv"), "new a"}, {dir.Path("out/a.json"), "new m"}});
  EXPECT_EQ(ReadFile(dir.Path("out/a.csv")), "new a");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "new m");
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.csv", "a.json"}));
}

// The streamed form: the pieces a producer hands its sink, in order; a producer that throws
// half-way leaves the old set and no temporary (its file's temporary already had content).
TEST(AtomicFile, StreamedFilesAreThePiecesOrNothing) {
  TempDir dir;
  WriteFilesAtomic(
      std::vector<StreamedFile>{{dir.Path("out/a.csv"),
                                 [](const TextSink& sink) {
                                   for (const char* piece : {"x,", "", "y\n", "1,2\n"}) sink(piece);
                                 }},
                                {dir.Path("out/a.json"), [](const TextSink& sink) { sink("m"); }}});
  EXPECT_EQ(ReadFile(dir.Path("out/a.csv")), "x,y\n1,2\n");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "m");
  const std::vector<StreamedFile> failing = {
      {dir.Path("out/a.csv"), [](const TextSink& sink) { sink("new a"); }},
      {dir.Path("out/b.csv"),
       [](const TextSink& sink) {
         sink("half");
         throw std::runtime_error("producer failed");
       }},
      {dir.Path("out/a.json"), [](const TextSink& sink) { sink("new m"); }}};
  EXPECT_THROW(WriteFilesAtomic(failing), std::runtime_error);
  EXPECT_EQ(ReadFile(dir.Path("out/a.csv")), "x,y\n1,2\n");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "m");
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.csv", "a.json"}));
}

TEST(AtomicFile, ReplacesAnOldResultSetWhole) {
  TempDir dir;
  dir.Write("out/a.csv", "old a");
  dir.Write("out/a.json", "old m");
  WriteFilesAtomic({{dir.Path("out/a.csv"), "new a"}, {dir.Path("out/a.json"), "new m"}});
  EXPECT_EQ(ReadFile(dir.Path("out/a.csv")), "new a");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "new m");
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.csv", "a.json"}));
}

TEST(AtomicFile, AFailingTargetLeavesTheOldSetAndNoTemporary) {
  TempDir dir;
  dir.Write("out/a.csv", "old a");
  dir.Write("out/a.json", "old m");
  fs::create_directories(dir.Path("out/b.csv"));
  EXPECT_INPUT_ERROR(
      WriteFilesAtomic({{dir.Path("out/a.csv"), "new a"},
                        {dir.Path("out/b.csv"), "new b"},
                        {dir.Path("out/a.json"), "new m"}}),
      dir.Path("out/b.csv") + ": cannot write: it is a directory; expected a writable location");
  EXPECT_EQ(ReadFile(dir.Path("out/a.csv")), "old a");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "old m");
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.csv", "a.json", "b.csv"}));
}

// A rename that fails in the middle of the commit, after other targets were already replaced,
// rolls every target back: a replaced file gets its old content again, a file that did not exist
// before is removed, and the old manifest is back in place. The failure is forced by a non-empty
// folder at the name the second target's old content would be moved aside to.
TEST(AtomicFile, AFailedRenameMidCommitRollsEveryTargetBack) {
  TempDir dir;
  dir.Write("out/b.csv", "old b");
  dir.Write("out/a.json", "old m");
  const std::string blocker = ".b.csv.patlab-old." + std::to_string(::getpid());
  dir.Write("out/" + blocker + "/keep", "x");
  try {
    WriteFilesAtomic({{dir.Path("out/new.csv"), "new n"},
                      {dir.Path("out/b.csv"), "new b"},
                      {dir.Path("out/a.json"), "new m"}});
    ADD_FAILURE() << "expected EnvironmentError";
  } catch (const EnvironmentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.Path("out/b.csv") + ": cannot write: ", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(ReadFile(dir.Path("out/b.csv")), "old b");
  EXPECT_EQ(ReadFile(dir.Path("out/a.json")), "old m");
  EXPECT_EQ(FileNames(dir.Path("out")), (std::set<std::string>{"a.json", "b.csv", blocker}));
}

TEST(AtomicFile, FailuresAreEnvironmentErrors) {
  TempDir dir;
  dir.Write("blocker", "a file");
  try {
    WriteFilesAtomic({{dir.Path("blocker/sub/a.csv"), "x"}});
    ADD_FAILURE() << "expected EnvironmentError";
  } catch (const EnvironmentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.Path("blocker/sub/a.csv") + ": cannot write: ", 0),
              0u)
        << e.what();
  }
  EXPECT_EQ(FileNames(dir.Path("")), (std::set<std::string>{"blocker"}));
}

TEST(AtomicFile, RefusesTheSamePathTwice) {
  TempDir dir;
  const std::string path = dir.Path("out/a.csv");
  EXPECT_INPUT_ERROR(WriteFilesAtomic({{path, "1"}, {path, "2"}}),
                     path + ": named twice in one result set; expected distinct output files");
  EXPECT_INPUT_ERROR(CheckWritable({path, path}),
                     path + ": named twice in one result set; expected distinct output files");
  EXPECT_FALSE(fs::exists(dir.Path("out")));
}

TEST(AtomicFile, CheckWritableCreatesNothingAndFindsBlockers) {
  TempDir dir;
  CheckWritable({dir.Path("new/deeper/a.csv"), dir.Path("a.json")});
  EXPECT_TRUE(FileNames(dir.Path("")).empty());
  dir.Write("blocker", "a file");
  EXPECT_INPUT_ERROR(CheckWritable({dir.Path("blocker/sub/a.csv")}),
                     dir.Path("blocker/sub/a.csv") + ": cannot write: " + dir.Path("blocker") +
                         " is not a directory; expected a writable location");
  fs::create_directories(dir.Path("out/a.csv"));
  EXPECT_INPUT_ERROR(
      CheckWritable({dir.Path("out/a.csv")}),
      dir.Path("out/a.csv") + ": cannot write: it is a directory; expected a writable location");
}

// "results/fig5.csv" in an empty working directory: no component of the folder exists yet, and
// the folder is made in the working directory.
TEST(AtomicFile, RelativeFoldersThatDoNotExistYetAreWritable) {
  TempDir dir;
  const fs::path before = fs::current_path();
  fs::current_path(dir.Path());
  CheckWritable({"results/fig5.csv", "a/b/c.json", "plain.csv"});
  EXPECT_TRUE(FileNames(dir.Path("")).empty());
  WriteFilesAtomic({{"a/b/c.csv", "1"}});
  EXPECT_EQ(ReadFile(dir.Path("a/b/c.csv")), "1");
  fs::current_path(before);
}

// SIGTERM while the temporaries are written: the handler removes them and the signal ends the
// process. The child makes its second temporary a FIFO first, so WriteFilesAtomic blocks opening
// it (no reader) after writing the first: the parent kills it there, deterministically.
TEST(AtomicFile, ASignalWhileWritingRemovesTheTemporaries) {
  TempDir dir;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    InstallSignalCleanup();
    ::mkfifo(dir.Path(".b.csv.patlab-tmp." + std::to_string(::getpid())).c_str(), 0600);
    WriteFilesAtomic({{dir.Path("a.csv"), "small"},
                      {dir.Path("b.csv"), "blocks"},
                      {dir.Path("a.json"), "manifest"}});
    ::_exit(0);
  }
  const std::string first_temp = dir.Path(".a.csv.patlab-tmp." + std::to_string(child));
  for (int k = 0; k < 600 && !fs::exists(first_temp); ++k) ::usleep(100'000);
  ASSERT_TRUE(fs::exists(first_temp));
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_TRUE(FileNames(dir.Path("")).empty());
}

TEST(AtomicFile, FileBaseNamesStayInsideTheirFolder) {
  EXPECT_TRUE(IsFileBaseName("fig5"));
  EXPECT_TRUE(IsFileBaseName(".."));  // "...csv" is still inside the folder
  EXPECT_FALSE(IsFileBaseName(""));
  EXPECT_FALSE(IsFileBaseName("../../x"));
  EXPECT_FALSE(IsFileBaseName("a/b"));
  EXPECT_FALSE(IsFileBaseName(std::string("a\0b", 3)));
  EXPECT_TRUE(IsFileBaseName(std::string(kMaxBaseNameBytes, 'a')));
  EXPECT_FALSE(IsFileBaseName(std::string(kMaxBaseNameBytes + 1, 'a')));
}

}  // namespace
}  // namespace patlab::io

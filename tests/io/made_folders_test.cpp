// Output folders made like `mkdir -p` and removed again when their output is not committed
// (io/made_folders.h), alone and through WriteFilesAtomic.
#include "patlab/io/made_folders.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"

namespace patlab::io {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// Every path under `dir`, relative to it.
std::set<std::string> Tree(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    names.insert(e.path().lexically_relative(dir).string());
  }
  return names;
}

TEST(MadeFolders, PlansTheMissingFoldersOutermostFirstAndMakesNothingUntilAsked) {
  TempDir dir;
  fs::create_directories(dir.Path("old"));
  MadeFolders made({dir.Path("old/new/deep"), dir.Path("old/new/other/"), dir.Path("old")});
  EXPECT_TRUE(Tree(dir.Path()) == std::set<std::string>{"old"});
  EXPECT_FALSE(made.Make(dir.Path("old/new/deep")));
  EXPECT_EQ(made.Made(), (std::vector<std::string>{dir.Path("old/new"), dir.Path("old/new/deep")}));
  EXPECT_FALSE(made.Make(dir.Path("old/new/other")));
  EXPECT_EQ(made.Made().back(), dir.Path("old/new/other"));
  EXPECT_TRUE(fs::is_directory(dir.Path("old/new/other")));
}

TEST(MadeFolders, RemovesWhatItMadeInnermostFirstUnlessKept) {
  TempDir dir;
  fs::create_directories(dir.Path("old"));
  {
    MadeFolders made({dir.Path("old/new/deep")});
    ASSERT_FALSE(made.Make(dir.Path("old/new/deep")));
    ASSERT_TRUE(fs::is_directory(dir.Path("old/new/deep")));
  }
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"old"}));  // the existing folder stays
  {
    MadeFolders made({dir.Path("old/new/deep")});
    ASSERT_FALSE(made.Make(dir.Path("old/new/deep")));
    made.Keep();
  }
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"old", "old/new", "old/new/deep"}));
}

// Only empty folders go: a file another writer put into "new" keeps it, its empty child goes.
TEST(MadeFolders, KeepsAFolderThatIsNoLongerEmpty) {
  TempDir dir;
  {
    MadeFolders made({dir.Path("new/deep")});
    ASSERT_FALSE(made.Make(dir.Path("new/deep")));
    dir.Write("new/theirs.txt", "x");
  }
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"new", "new/theirs.txt"}));
}

// A folder another process made between the plan and the mkdir is not this object's.
TEST(MadeFolders, NeverRemovesAFolderItDidNotMake) {
  TempDir dir;
  {
    MadeFolders made({dir.Path("new/deep")});
    fs::create_directories(dir.Path("new"));
    ASSERT_FALSE(made.Make(dir.Path("new/deep")));
    EXPECT_EQ(made.Made(), std::vector<std::string>{dir.Path("new/deep")});
  }
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"new"}));
}

TEST(MadeFolders, AFileWhereAFolderGoesIsNotADirectoryAndLeavesNothing) {
  TempDir dir;
  {
    MadeFolders made({dir.Path("new/file/deep")});
    ASSERT_FALSE(made.Make(dir.Path("new")));
    dir.Write("new/file", "x");
    EXPECT_EQ(made.Make(dir.Path("new/file/deep")),
              std::make_error_code(std::errc::not_a_directory));
    fs::remove(dir.Path("new/file"));
  }
  EXPECT_TRUE(Tree(dir.Path()).empty());
}

TEST(MadeFolders, RelativeFoldersAreMadeInTheWorkingDirectory) {
  TempDir dir;
  const fs::path before = fs::current_path();
  fs::current_path(dir.Path());
  {
    MadeFolders made({"new/deep/"});
    EXPECT_FALSE(made.Make("new/deep/"));
    EXPECT_EQ(made.Made(), (std::vector<std::string>{"new", "new/deep"}));
    EXPECT_TRUE(fs::is_directory("new/deep"));
  }
  EXPECT_TRUE(Tree(".").empty());
  fs::current_path(before);
}

// WriteFilesAtomic: a set that fails before its commit leaves none of the folders it made; a
// committed one keeps them.
TEST(MadeFolders, AResultSetThatFailsLeavesNoFolderItMade) {
  TempDir dir;
  fs::create_directories(dir.Path("old"));
  const std::vector<StreamedFile> failing = {
      {dir.Path("old/new/a.csv"), [](const TextSink& sink) { sink("a"); }},
      {dir.Path("old/new/deep/b.csv"),
       [](const TextSink& sink) {
         sink("half");
         throw std::runtime_error("the producer failed");
       }},
      {dir.Path("old/new/a.json"), [](const TextSink& sink) { sink("m"); }}};
  EXPECT_THROW(WriteFilesAtomic(failing), std::runtime_error);
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"old"}));
  WriteFilesAtomic({{dir.Path("old/new/deep/b.csv"), "b"}, {dir.Path("old/new/a.json"), "m"}});
  EXPECT_EQ(Tree(dir.Path()), (std::set<std::string>{"old", "old/new", "old/new/a.json",
                                                     "old/new/deep", "old/new/deep/b.csv"}));
}

// SIGTERM while a result set's temporaries are written into folders the writer made: the handler
// removes the temporaries and then the folders. The child's producer waits after its first piece.
TEST(MadeFolders, ASignalWhileWritingRemovesTheFoldersItMade) {
  TempDir dir;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    InstallSignalCleanup();
    WriteFilesAtomic(std::vector<StreamedFile>{
        {dir.Path("new/deep/a.csv"),
         [](const TextSink& sink) {
           sink("first piece");
           for (;;) ::pause();
         }},
        {dir.Path("new/deep/a.json"), [](const TextSink& sink) { sink("m"); }}});
    ::_exit(0);
  }
  const std::string temp = dir.Path("new/deep/.a.csv.patlab-tmp." + std::to_string(child));
  std::error_code ec;
  for (int k = 0; k < 600 && (fs::file_size(temp, ec) == 0 || ec); ++k) ::usleep(100'000);
  ASSERT_TRUE(fs::exists(temp));
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_TRUE(Tree(dir.Path()).empty());
}

}  // namespace
}  // namespace patlab::io

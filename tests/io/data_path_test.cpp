// Data found by name: the roots in order, the kind's folders, paths taken as they are, and the
// message for a name that is not there.
#include "patlab/io/data_path.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "../expect_error.h"
#include "../test_util.h"

namespace patlab::io {
namespace {

using testing::TempDir;

TEST(DataPath, FindsNamesByKindInTheRootsInOrder) {
  TempDir first, second;
  first.Write("patterns/butterfly.toml", "a");
  second.Write("patterns/butterfly.toml", "b");
  second.Write("patterns/triangle.toml", "c");
  second.Write("experiments/fig5.toml", "d");
  second.Write("experiments/detector.toml", "e");
  second.Write("settings/ssl-frame.toml", "f");
  second.Write("experiments/fields/ssl-2009.toml", "g");
  const std::vector<std::string> roots = {first.Path(), second.Path()};
  EXPECT_EQ(FindData("butterfly", DataKind::kPattern, roots),
            first.Path("patterns/butterfly.toml"));
  EXPECT_EQ(FindData("triangle", DataKind::kPattern, roots), second.Path("patterns/triangle.toml"));
  EXPECT_EQ(FindData("fig5.toml", DataKind::kExperiment, roots),
            second.Path("experiments/fig5.toml"));
  EXPECT_EQ(FindData("ssl-frame", DataKind::kSettings, roots),
            second.Path("settings/ssl-frame.toml"));
  EXPECT_EQ(FindData("detector", DataKind::kSettings, roots),
            second.Path("experiments/detector.toml"));
  EXPECT_EQ(FindData("ssl-2009", DataKind::kField, roots),
            second.Path("experiments/fields/ssl-2009.toml"));
  // An existing file is itself, whatever its kind.
  const std::string file = first.Write("mine.toml", "x");
  EXPECT_EQ(FindData(file, DataKind::kPattern, roots), file);
  EXPECT_EQ(DataNames(DataKind::kPattern, roots),
            (std::vector<std::string>{"butterfly", "triangle"}));
}

TEST(DataPath, ANameNotFoundListsTheFoldersAndTheCloseNames) {
  TempDir root;
  root.Write("patterns/butterfly.toml", "a");
  EXPECT_INPUT_ERROR(FindData("buterfly", DataKind::kPattern, {root.Path()}),
                     "pattern 'buterfly' not found; expected an existing file or a name in " +
                         root.Path("patterns") + "/ (did you mean 'butterfly'?)");
  // A path is left to its loader, which says the file is missing.
  EXPECT_EQ(FindData("no/such/butterfly.toml", DataKind::kPattern, {root.Path()}),
            "no/such/butterfly.toml");
  EXPECT_INPUT_ERROR(FindData("fig5", DataKind::kExperiment, {}),
                     "experiment 'fig5' not found; expected an existing file or a name in a data "
                     "folder (none found: set PATLAB_DATA)");
}

TEST(DataPath, RootsAreTheEnvironmentTheInstalledShareAndTheBuildTreesSource) {
  TempDir prefix, source;
  std::filesystem::create_directories(prefix.Path("bin"));
  std::filesystem::create_directories(prefix.Path("share/patlab"));
  std::filesystem::create_directories(source.Path("patterns"));
  prefix.Write("bin/CMakeCache.txt",
               "X:STRING=1\npatlab_SOURCE_DIR:STATIC=" + source.Path() + "\n");
  const auto canonical = [](const std::string& p) {
    return std::filesystem::weakly_canonical(p).string();
  };
  EXPECT_EQ(
      DataRoots(prefix.Path("bin"), source.Path("patterns").c_str()),
      (std::vector<std::string>{canonical(source.Path("patterns")),
                                canonical(prefix.Path("share/patlab")), canonical(source.Path())}));
  EXPECT_EQ(
      DataRoots(prefix.Path("bin"), ""),
      (std::vector<std::string>{canonical(prefix.Path("share/patlab")), canonical(source.Path())}));
  EXPECT_TRUE(DataRoots(prefix.Path("nothing"), "/no/such/folder").empty());
}

}  // namespace
}  // namespace patlab::io

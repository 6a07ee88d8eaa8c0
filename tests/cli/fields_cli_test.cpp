// patlab fields end to end: the list of shipped models and families, a family, one model's
// landmarks, lines and arcs, a field file by path, and a name that is not a model.
#include <gtest/gtest.h>

#include <string>

#include "../test_util.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::RunCommand;

TEST(FieldsCli, ListsEveryModelAndFamily) {
  const auto r = RunCommand(kPatlab + " fields");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name :
       {"ssl-2008 ", "ssl-2009 ", "ssl-2012 ", "ssl-2014 ", "ssl-2015 ", "ssl-2018 ",
        "ssl-2019-div-b ", "ssl-div-a ", "ssl-div-b ", "vss ", "vss-5v5 "}) {
    EXPECT_NE(r.out.find(std::string("\n") + name), std::string::npos) << name;
  }
  EXPECT_NE(r.out.find("\nssl-div-b        9000 x 6000 mm, boundary 300 mm"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  ssl: ssl-div-a, ssl-div-b, ssl-2019-div-b, ssl-2018, ssl-2015, "
                       "ssl-2014, ssl-2012, ssl-2009, ssl-2008\n  vss: vss-5v5, vss\n"),
            std::string::npos)
      << r.out;
}

TEST(FieldsCli, AFamilyListsItsModelsNewestFirst) {
  const auto r = RunCommand(kPatlab + " fields vss");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("family vss (newest first):\nvss-5v5 "), 0u) << r.out;
  EXPECT_NE(r.out.find("\nvss              1500 x 1300 mm, boundary 0 mm"), std::string::npos)
      << r.out;
}

TEST(FieldsCli, AModelPrintsItsLandmarksLinesAndArcs) {
  const auto r = RunCommand(kPatlab + " fields ssl-2009");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("field ssl-2009 (family ssl)\n"), 0u) << r.out;
  EXPECT_NE(r.out.find("\n  corner_pos_left              3025 2025\n"), std::string::npos);
  EXPECT_NE(r.out.find("\n  penalty_mark_neg             -2575 0\n"), std::string::npos);
  EXPECT_NE(r.out.find("\n  halfway                      0 -2025  0 2025\n"), std::string::npos);
  EXPECT_NE(r.out.find("\n  defense_arc_left_neg         -3025 175 500  0 90\n"),
            std::string::npos);
  EXPECT_NE(r.out.find("\n  centre_circle                0 0 500  0 360 (full circle)\n"),
            std::string::npos);
  // A field file by path reads the same.
  const auto path =
      RunCommand(kPatlab + " fields " + PATLAB_SOURCE_DIR + "/experiments/fields/ssl-2009.toml");
  EXPECT_EQ(path.exit_code, 0) << path.err;
  EXPECT_EQ(path.out, r.out);
}

TEST(FieldsCli, AnUnknownNameIsExit2WithTheCloseNames) {
  const auto r = RunCommand(kPatlab + " fields ssl-2010");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.find("patlab fields: field 'ssl-2010' not found; expected an existing file or "
                       "a name in "),
            0u)
      << r.err;
  EXPECT_NE(r.err.find("did you mean"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

}  // namespace
}  // namespace patlab::cli

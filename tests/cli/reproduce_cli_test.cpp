// End-to-end: `patlab reproduce --check` passes on the committed results and names a committed
// file whose numbers moved (docs/reproduce.md).
#include <gtest/gtest.h>

#include <filesystem>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kPatlab;
using testing::RunCommand;

const std::string kRoot = PATLAB_SOURCE_DIR;

TEST(ReproduceCli, CheckPassesOnTheCommittedResultsAndNamesAnEditedFile) {
  const auto ok =
      RunCommand(kPatlab + " reproduce --check --root " + kRoot + " --out " + kRoot + "/results");
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_EQ(ok.out, "");
  // A copy of the results with one Table I number, a Fig. 5 std (by 1e-6 relative), a Wilcoxon
  // rank sum (by 10,000) and fig5.json's seed changed, paper.md and the figures missing;
  // table1.json as committed (its run keys and paths differ from the run's).
  testing::TempDir dir;
  for (const char* name :
       {"fig5.csv", "table1.csv", "table1_tests.csv", "fig5.json", "table1.json"}) {
    std::string text = testing::ReadFile(kRoot + "/results/" + name);
    if (std::string(name) == "fig5.json") {
      const size_t at = text.find("\"seed\": 2003");
      ASSERT_NE(at, std::string::npos);
      text.replace(at, 12, "\"seed\": 2004");
    }
    const auto replace = [&text](const std::string& from, const std::string& to) {
      const size_t at = text.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      text.replace(at, from.size(), to);
    };
    if (std::string(name) == "fig5.csv") {
      replace("\nbutterfly,fast,1,100000,isotropic,0.001118462505,0.4513416095,",
              "\nbutterfly,fast,1,100000,isotropic,0.001118462505,0.4513420608,");
    }
    if (std::string(name) == "table1_tests.csv") {
      replace("\nest,x,40mm,50mm,12450,0.3553,0.3336,41906986,35600489,",
              "\nest,x,40mm,50mm,12450,0.3553,0.3336,41916986,35590489,");
    }
    if (std::string(name) == "table1.csv") {
      const size_t at = text.find("\n40mm,12450,");
      ASSERT_NE(at, std::string::npos);
      text[at + 12] = text[at + 12] == '9' ? '8' : static_cast<char>(text[at + 12] + 1);
    }
    dir.Write(name, text);
  }
  const auto bad =
      RunCommand(kPatlab + " reproduce --check -q --root " + kRoot + " --out " + dir.Path());
  EXPECT_EQ(bad.exit_code, 1);
  // Each named by file, line, column, both values and the tolerance.
  for (const std::string& line :
       {"DIFFERS " + dir.Path("table1.csv") +
            ": line 2, column est_sx_mm (continuous): 0.5224 vs committed 1.5224; tolerance "
            "+-3.0458e-09 (relative drift 2e-9 + 1e-12)\n",
        "DIFFERS " + dir.Path("fig5.csv") +
            ": line 112, column std_x_mm (continuous): 0.4513416095 vs committed 0.4513420608; "
            "tolerance +-9.03684e-10 (relative drift 2e-9 + 1e-12)\n",
        "DIFFERS " + dir.Path("table1_tests.csv") +
            ": line 2, column r_plus (rank sum): 41906986 vs committed 41916986; tolerance +-"}) {
    EXPECT_NE(bad.out.find(line), std::string::npos) << line << "\n" << bad.out;
  }
  EXPECT_NE(
      bad.out.find("DIFFERS " + dir.Path("paper.md") + ": missing; expected the committed file"),
      std::string::npos)
      << bad.out;
  EXPECT_NE(bad.out.find("DIFFERS " + dir.Path("fig5.json") + ": seed 2003; committed: 2004"),
            std::string::npos)
      << bad.out;
  EXPECT_NE(bad.out.find("DIFFERS " + dir.Path("fig2.png") +
                         ": missing; expected the committed figure (Figs. 2, 3, 6)"),
            std::string::npos)
      << bad.out;
  EXPECT_EQ(bad.out.find(dir.Path("table1.json") + ":"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace patlab

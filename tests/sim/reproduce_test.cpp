// The comparison behind `patlab reproduce --check` (src/patlab/sim/reproduce.h).
#include "patlab/sim/reproduce.h"

#include <gtest/gtest.h>

namespace patlab::sim {
namespace {

TEST(Reproduce, CompareResultTextAcceptsTheCrossMachineToleranceOnly) {
  const std::string a = "pattern,std_mm,trials\nsimple,0.8680123456,100000\nlinear,,5\n";
  EXPECT_EQ(CompareResultText(a, a), "");
  // One unit in the 10th digit is within 2e-9 relative.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123457,100000\nlinear,,5\n"),
            "");
  // Two units in the 7th digit are not.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680143456,100000\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simple,0.8680143456,100000");
  // A count that moves by one, an empty cell that fills, a text cell that changes.
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123456,100001\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simple,0.8680123456,100001");
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimple,0.8680123456,100000\nlinear,1,5\n"),
            "line 3: linear,,5; committed: linear,1,5");
  EXPECT_EQ(CompareResultText(a, "pattern,std_mm,trials\nsimplx,0.8680123456,100000\nlinear,,5\n"),
            "line 2: simple,0.8680123456,100000; committed: simplx,0.8680123456,100000");
  // Rounding noise near zero (the sigma = 0 rows) within 1e-12 absolute.
  EXPECT_EQ(CompareResultText("m\n1.2e-13\n", "m\n-3.1e-13\n"), "");
  EXPECT_EQ(CompareResultText("m\n1.2e-13\n", "m\n"), "line 2: extra line 1.2e-13");
  EXPECT_EQ(CompareResultText("m\n", "m\n7\n"), "line 2: missing line 7");
}

}  // namespace
}  // namespace patlab::sim

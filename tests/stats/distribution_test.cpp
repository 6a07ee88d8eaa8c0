#include "stats/distribution.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "fixtures.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Histogram, MatchesNumpyFixtures) {
  int checked = 0;
  for (const auto& c : Fixtures().at("histogram")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const auto bins = c.at("bins").get<std::size_t>();
    const Histogram h = c.at("range").is_null()
                            ? MakeHistogram(x, bins)
                            : MakeHistogram(x, bins, c.at("range").at(0).get<double>(),
                                            c.at("range").at(1).get<double>());
    EXPECT_EQ(h.counts, c.at("expect").at("counts").get<std::vector<std::size_t>>());
    EXPECT_EQ(h.edges, c.at("expect").at("edges").get<std::vector<double>>());
    ++checked;
  }
  EXPECT_GE(checked, 4);
}

TEST(Histogram, HandComputedEdges) {
  // [0, 1) [1, 2] : the last bin is closed, values outside the range are dropped.
  const std::vector<double> x = {-1.0, 0.0, 0.5, 1.0, 2.0, 3.0};
  const Histogram h = MakeHistogram(x, 2, 0.0, 2.0);
  EXPECT_EQ(h.counts, (std::vector<std::size_t>{2, 2}));
  EXPECT_EQ(h.edges, (std::vector<double>{0.0, 1.0, 2.0}));
  EXPECT_THROW(MakeHistogram(x, 0, 0.0, 1.0), InputError);
}

TEST(Ecdf, MatchesNumpyFixture) {
  for (const auto& c : Fixtures().at("ecdf")) {
    const EcdfTable t = MakeEcdf(Sample(c.at("x")));
    EXPECT_EQ(t.values, c.at("expect").at("values").get<std::vector<double>>());
    EXPECT_EQ(t.cumulative_fraction,
              c.at("expect").at("cumulative_fraction").get<std::vector<double>>());
  }
}

TEST(Ecdf, HandComputedWithTies) {
  const EcdfTable t = MakeEcdf(std::vector<double>{3.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(t.values, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(t.cumulative_fraction, (std::vector<double>{0.25, 0.5, 1.0}));
  EXPECT_THROW(MakeEcdf(std::vector<double>{}), InputError);
}

}  // namespace
}  // namespace patlab::stats

// Tests of stage timing (src/patlab/core/timeprofile.h).
#include "patlab/core/timeprofile.h"

#include <gtest/gtest.h>

#include <string_view>

namespace patlab {
namespace {

TEST(TimeProfile, DisabledRecordsNothing) {
  TimeProfile profile;
  EXPECT_FALSE(profile.enabled());
  profile.Start();
  profile.Stamp("1 candidates");
  profile.Stamp("2 neighbours");
  EXPECT_TRUE(profile.entries().empty());
  EXPECT_EQ(profile.total_seconds(), 0.0);
}

TEST(TimeProfile, EnabledStampsEachStageInOrder) {
  TimeProfile profile(/*enabled=*/true);
  profile.Start();
  profile.Stamp("1 candidates");
  profile.Stamp("2 neighbours");
  profile.Stamp("1 candidates");  // a second frame's stage 1 adds to the first entry
  ASSERT_EQ(profile.entries().size(), 2u);
  EXPECT_EQ(profile.entries()[0].stage, "1 candidates");
  EXPECT_EQ(profile.entries()[0].count, 2);
  EXPECT_EQ(profile.entries()[1].stage, "2 neighbours");
  EXPECT_EQ(profile.entries()[1].count, 1);
  for (const TimeProfile::Entry& e : profile.entries()) EXPECT_GE(e.seconds, 0.0);
}

TEST(TimeProfile, AddSumsByStageName) {
  TimeProfile profile;
  profile.Add("3 decode", 0.25);
  profile.Add("3 decode", 0.5, 3);
  ASSERT_EQ(profile.entries().size(), 1u);
  EXPECT_EQ(profile.entries()[0].seconds, 0.75);
  EXPECT_EQ(profile.entries()[0].count, 4);
  EXPECT_EQ(profile.total_seconds(), 0.75);
  profile.Clear();
  EXPECT_TRUE(profile.entries().empty());
}

TEST(TimeProfile, PlusEqualsMergesByStageKeepingOrder) {
  TimeProfile a, b;
  a.Add("1 candidates", 1.0);
  a.Add("2 neighbours", 2.0);
  b.Add("2 neighbours", 0.5);
  b.Add("4 pose", 4.0);
  b.Add("1 candidates", 0.25, 2);
  a += b;
  ASSERT_EQ(a.entries().size(), 3u);
  EXPECT_EQ(a.entries()[0].stage, "1 candidates");
  EXPECT_EQ(a.entries()[0].seconds, 1.25);
  EXPECT_EQ(a.entries()[0].count, 3);
  EXPECT_EQ(a.entries()[1].stage, "2 neighbours");
  EXPECT_EQ(a.entries()[1].seconds, 2.5);
  EXPECT_EQ(a.entries()[2].stage, "4 pose");  // new stages are appended in the other's order
  EXPECT_EQ(a.total_seconds(), 7.75);
  EXPECT_EQ(b.entries().size(), 3u);  // the other profile is unchanged
}

}  // namespace
}  // namespace patlab

// EditDistance against distances counted by hand, and CloseNames' rule (distance <= 2, else a
// unique prefix).
#include "patlab/core/close_names.h"

#include <gtest/gtest.h>

namespace patlab {
namespace {

TEST(CloseNames, EditDistanceCountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(EditDistance("", ""), 0);
  EXPECT_EQ(EditDistance("abc", ""), 3);
  EXPECT_EQ(EditDistance("", "ab"), 2);
  EXPECT_EQ(EditDistance("trials", "trials"), 0);
  EXPECT_EQ(EditDistance("trails", "trials"), 1);  // one swap, not two substitutions
  EXPECT_EQ(EditDistance("sigma", "sigmas"), 1);
  EXPECT_EQ(EditDistance("simulte", "simulate"), 1);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("ca", "abc"), 3);  // optimal string alignment: no edit of a swapped pair
}

TEST(CloseNames, SuggestsTheClosestWithinTwoEdits) {
  const std::vector<std::string> commands = {"simulate", "evaluate", "compare", "merge", "track"};
  EXPECT_EQ(CloseNames("simulat", commands), std::vector<std::string>{"simulate"});
  EXPECT_EQ(CloseNames("evalute", commands), std::vector<std::string>{"evaluate"});
  EXPECT_EQ(CloseNames("trakc", commands), std::vector<std::string>{"track"});
  EXPECT_TRUE(CloseNames("render", commands).empty());
  EXPECT_TRUE(CloseNames("x", {"j", "q"}).empty());
}

TEST(CloseNames, FallsBackToAUniquePrefix) {
  const std::vector<std::string> flags = {"--trials", "--threads", "--outlier-probability"};
  EXPECT_EQ(CloseNames("--outlier", flags), std::vector<std::string>{"--outlier-probability"});
  EXPECT_TRUE(CloseNames("--t", flags).empty());  // two candidates start with it
}

TEST(CloseNames, QuotesAlternativesForAMessage) {
  EXPECT_EQ(QuotedAlternatives({"a"}), "'a'");
  EXPECT_EQ(QuotedAlternatives({"a", "b"}), "'a' or 'b'");
  EXPECT_EQ(QuotedAlternatives({"a", "b", "c"}), "'a', 'b' or 'c'");
}

}  // namespace
}  // namespace patlab

#include "patlab/core/error.h"

#include <gtest/gtest.h>

#include <string>

namespace patlab {
namespace {

TEST(Error, EscapeForMessageShowsControlAndInvalidBytes) {
  EXPECT_EQ(EscapeForMessage("plain text, ümlaut"), "plain text, ümlaut");
  EXPECT_EQ(EscapeForMessage(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(EscapeForMessage("bad\xff"), "bad\\xff");
  EXPECT_EQ(EscapeForMessage("tab\there\n"), "tab\\x09here\\x0a");
  EXPECT_EQ(EscapeForMessage("\xc3"), "\\xc3");  // a truncated sequence
}

TEST(Error, EscapeForMessageCutsLongText) {
  EXPECT_EQ(EscapeForMessage(std::string(10, 'x'), 4), "xxxx... (10 bytes)");
  EXPECT_EQ(EscapeForMessage(std::string(4, 'x'), 4), "xxxx");
  EXPECT_EQ(EscapeForMessage(std::string(10'000'000, 'y')).size(), 120u + 20u);
}

TEST(Error, IsValidUtf8FollowsRfc3629) {
  EXPECT_TRUE(IsValidUtf8(""));
  EXPECT_TRUE(IsValidUtf8("ascii"));
  EXPECT_TRUE(IsValidUtf8("\xc3\xbc"));          // ü
  EXPECT_TRUE(IsValidUtf8("\xe2\x82\xac"));      // €
  EXPECT_TRUE(IsValidUtf8("\xf0\x9f\x98\x80"));  // U+1F600
  EXPECT_FALSE(IsValidUtf8("\xff"));
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));      // a surrogate
  EXPECT_FALSE(IsValidUtf8("\xf4\x90\x80\x80"));  // above U+10FFFF
  EXPECT_FALSE(IsValidUtf8("\xe2\x82"));          // truncated
}

}  // namespace
}  // namespace patlab

// Names that reach a file name or a results cell (io/name.h).
#include "patlab/io/name.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "../expect_error.h"
#include "patlab/io/atomic_file.h"

namespace patlab::io {
namespace {

TEST(Name, AcceptsUtf8WithoutSeparatorsOrControlCharacters) {
  for (const std::string& good : std::initializer_list<std::string>{
           "fig5", "ssl-standard", "..", "a b", "Grüße", "名前", std::string(kMaxNameBytes, 'a')}) {
    EXPECT_EQ(NameProblem(good), "") << good;
  }
}

TEST(Name, SaysWhatIsWrong) {
  EXPECT_EQ(NameProblem(""), "is empty");
  EXPECT_EQ(NameProblem(std::string(kMaxNameBytes + 1, 'a')), "is longer than 200 bytes");
  EXPECT_EQ(NameProblem("../x"), "holds '/'");
  EXPECT_EQ(NameProblem("a\\b"), "holds '\\'");
  EXPECT_EQ(NameProblem("a\nb"), "holds a control character or NUL");
  EXPECT_EQ(NameProblem(std::string("a\0b", 3)), "holds a control character or NUL");
  EXPECT_EQ(NameProblem("a\x7f"), "holds a control character or NUL");
  EXPECT_EQ(NameProblem("bad\xff"), "is not valid UTF-8");
  EXPECT_EQ(NameProblem("\xc3"), "is not valid UTF-8");  // a cut two-byte sequence
}

TEST(Name, CheckNameNamesTheFlagAndTheRule) {
  CheckName("fig5", "--name");
  EXPECT_INPUT_ERROR(CheckName("../../x", "--name"),
                     "--name '../../x' holds '/'; expected a non-empty name of at most 200 bytes "
                     "of UTF-8 without '/', '\\', control characters or NUL");
  EXPECT_INPUT_ERROR(CheckName("a\tb", "pattern name"),
                     "pattern name 'a\\x09b' holds a control character or NUL; expected a "
                     "non-empty name of at most 200 bytes of UTF-8 without '/', '\\', control "
                     "characters or NUL");
}

// A file base name is a name by the same rule.
TEST(Name, FileBaseNamesFollowTheNameRule) {
  EXPECT_TRUE(IsFileBaseName("fig5"));
  EXPECT_FALSE(IsFileBaseName("a\nb"));
  EXPECT_FALSE(IsFileBaseName("bad\xff"));
  EXPECT_FALSE(IsFileBaseName("a\\b"));
}

}  // namespace
}  // namespace patlab::io

// The malformed-input suite (docs/hardening.md): every input patlab reads, broken in
// the ways a hostile or careless user breaks it. Each case runs the real binary on files written
// into a fresh directory and asserts the exit status (2 bad input, 1 environment), the whole
// message on stderr word for word, an empty stdout, and that no output appeared: the directory
// holds exactly the files the case wrote, no result, no temporary.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "../test_util.h"
#include "malformed_cases.h"
#include "malformed_frame_cases.h"

namespace patlab {
namespace {

namespace fs = std::filesystem;

std::string Substitute(std::string text, const std::string& dir) {
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"{dir}", dir}, {"{src}", PATLAB_SOURCE_DIR}}) {
    for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at)) {
      text.replace(at, key.size(), value);
      at += value.size();
    }
  }
  return text;
}

std::set<std::string> Listing(const std::string& dir) {
  // Error codes, not exceptions: a case's symbolic-link loop must not stop the listing.
  std::set<std::string> names;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    names.insert(it->path().lexically_relative(dir).string());
  }
  EXPECT_FALSE(ec) << ec.message();
  return names;
}

class Malformed : public ::testing::TestWithParam<testing::MalformedCase> {};

TEST_P(Malformed, ExitsWithTheMessageAndWritesNothing) {
  const testing::MalformedCase& c = GetParam();
  testing::TempDir dir;
  for (const auto& [name, content] : c.files) {
    dir.Write(name, Substitute(content, dir.Path("")));
  }
  if (c.setup != nullptr) c.setup(dir.Path(""));
  const std::set<std::string> before = Listing(dir.Path(""));
  const std::string prefix = c.shell_prefix != nullptr ? std::string(c.shell_prefix) + " " : "";
  const auto r = testing::RunCommand(prefix + PATLAB_BINARY + " " +
                                     Substitute(c.arguments, dir.Path("")) + " </dev/null");
  if (const char* dump = std::getenv("PATLAB_MALFORMED_DUMP")) {
    std::string err = r.err;
    for (const auto& [from, to] : {std::pair<std::string, std::string>{dir.Path(""), "{dir}"},
                                   {PATLAB_SOURCE_DIR, "{src}"}}) {
      for (size_t at = err.find(from); at != std::string::npos; at = err.find(from, at)) {
        err.replace(at, from.size(), to);
      }
    }
    std::ofstream(std::string(dump) + "/" + c.name + ".err", std::ios::binary) << err;
    std::ofstream(std::string(dump) + "/" + c.name + ".code") << r.exit_code;
  }
  EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
  EXPECT_EQ(r.err, Substitute(c.message, dir.Path("")) + "\n");
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(Listing(dir.Path("")), before) << "output or temporary files appeared";
}

INSTANTIATE_TEST_SUITE_P(AllInputs, Malformed, ::testing::ValuesIn(testing::MalformedCases()),
                         [](const ::testing::TestParamInfo<testing::MalformedCase>& info) {
                           return std::string(info.param.name);
                         });

INSTANTIATE_TEST_SUITE_P(FrameSettings, Malformed,
                         ::testing::ValuesIn(testing::FrameSettingsMalformedCases()),
                         [](const ::testing::TestParamInfo<testing::MalformedCase>& info) {
                           return std::string(info.param.name);
                         });

TEST(MalformedSuite, CoversAtLeastThreeHundredCasesWithDistinctNames) {
  std::set<std::string> names;
  for (const testing::MalformedCase& c : testing::MalformedCases()) names.insert(c.name);
  for (const testing::MalformedCase& c : testing::FrameSettingsMalformedCases()) {
    names.insert(c.name);
  }
  EXPECT_GE(names.size(), 300u);
  EXPECT_EQ(names.size(),
            testing::MalformedCases().size() + testing::FrameSettingsMalformedCases().size());
}

}  // namespace
}  // namespace patlab

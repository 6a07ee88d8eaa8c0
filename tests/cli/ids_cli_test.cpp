// patlab ids, end to end: runs the built binary.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct IdsRun {
  int status = -1;
  std::string out;  // stdout and stderr
};

IdsRun RunPatlab(const std::string& args) {
  const std::string command = "cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " " + args + " 2>&1";
  IdsRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

TEST(IdsCli, PrintsTableTwo) {
  const IdsRun run = RunPatlab("ids simple linear triangle butterfly");
  EXPECT_EQ(run.status, 0);
  EXPECT_EQ(run.out,
            "IDs per ID palette size (paper Table II; key patch and key colour excluded), "
            "symmetry tolerance 10 mm\n"
            "\n"
            "pattern    slots  rotations  2 colours   3 colours   4 colours\n"
            "simple     1      1          2           3           4\n"
            "linear     2      2          1           3           6\n"
            "triangle   3      3          2           8           20\n"
            "butterfly  4      1          16          81          256\n"
            "\n"
            "rotations: rotations about the key that geometry cannot tell apart and colours "
            "must decide\n");
}

TEST(IdsCli, ListsTheIds) {
  const IdsRun run = RunPatlab("ids linear --colors 3 --list");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("linear, 3 colours: 3 IDs (slots = patches 1 2)\n"
                         "     0  A B\n"
                         "     1  A C\n"
                         "     2  B C\n"),
            std::string::npos)
      << run.out;
}

TEST(IdsCli, ToleranceChangesTheSymmetry) {
  const IdsRun run = RunPatlab("ids ssl-standard --colors 2 --tolerance 30");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("ssl-standard  4      4          3\n"), std::string::npos) << run.out;
}

TEST(IdsCli, BadInputExitsTwoWithMessage) {
  IdsRun run = RunPatlab("ids simple --colors 2,x");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out,
            "patlab ids: --colors has 'x'; expected comma-separated integers from 1 to 16, e.g. "
            "2,3,4\n");
  run = RunPatlab("ids hexagon");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out,
            "patlab ids: pattern 'hexagon' not found; expected a pattern file path or a name in "
            "patterns/\n");
  run = RunPatlab("ids");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out,
            "patlab ids: missing PATTERN; expected 'patlab ids PATTERN... [--colors 2,3,4]' (see "
            "--help)\n");
  run = RunPatlab("ids simple --tolerance -1");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out, "patlab ids: --tolerance is -1; expected a distance in mm >= 0\n");
}

TEST(IdsCli, HelpHasExamples) {
  const IdsRun run = RunPatlab("ids --help");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("patlab ids ssl-standard --colors 2 --list"), std::string::npos);
}

}  // namespace

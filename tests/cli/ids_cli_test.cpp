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
  EXPECT_EQ(
      run.out,
      "IDs per ID palette size (paper Table II; key patch and key colour excluded), symmetry "
      "tolerance 10 mm\n"
      "\n"
      "pattern    slots  rotations  2 colours   3 colours   4 colours\n"
      "simple     1      1          2           3           4\n"
      "linear     2      2          1           3           6\n"
      "triangle   3      3          2           8           20\n"
      "butterfly  4      1          16          81          256\n"
      "\n"
      "rotations: rotations about the key that geometry cannot tell apart and ID colours must "
      "decide\n"
      "\n"
      "simple: accepted shifts {0}, group generated {0}: geometry and fixed colours fix the "
      "rotation\n"
      "  shift  angle deg  residual mm  geometry (tolerance 10 mm)                      rotation "
      "decided by\n"
      "  0      0.0        0.00         identity                                       -\n"
      "\n"
      "linear: accepted shifts {0, 1}, group generated {0, 1}, ID colours decide among {0, 1}: 2 "
      "rotations\n"
      "  shift  angle deg  residual mm  geometry (tolerance 10 mm)                      rotation "
      "decided by\n"
      "  0      0.0        0.00         identity                                       -\n"
      "  1      180.0      0.00         accepted: residual <= tolerance                ID colours\n"
      "\n"
      "triangle: accepted shifts {0, 1, 2}, group generated {0, 1, 2}, ID colours decide among {0, "
      "1, 2}: 3 rotations\n"
      "  shift  angle deg  residual mm  geometry (tolerance 10 mm)                      rotation "
      "decided by\n"
      "  0      0.0        0.00         identity                                       -\n"
      "  1      120.0      0.00         accepted: residual <= tolerance                ID colours\n"
      "  2      240.0      0.00         accepted: residual <= tolerance                ID colours\n"
      "\n"
      "butterfly: accepted shifts {0}, group generated {0}: geometry and fixed colours fix the "
      "rotation\n"
      "  shift  angle deg  residual mm  geometry (tolerance 10 mm)                      rotation "
      "decided by\n"
      "  0      0.0        0.00         identity                                       -\n"
      "  1      90.0       27.96        rejected: residual > tolerance                 geometry\n"
      "  2      180.0      27.96        rejected: residual > tolerance                 geometry\n"
      "  3      270.0      27.96        rejected: residual > tolerance                 geometry\n");
}

// The irregular pentagon: geometry accepts shifts 2 and 3 only, colours must decide all five
// rotations of the group they generate, and the table says why for each shift.
TEST(IdsCli, NearSymmetricPentagonCountsTheGroupGenerated) {
  const IdsRun run = RunPatlab("ids tests/data/detect/pentagon-irregular.toml");
  EXPECT_EQ(run.status, 0);
  for (const char* line :
       {"pentagon-irregular  5      5          6           48          204\n",
        "pentagon-irregular: accepted shifts {0, 2, 3}, group generated {0, 1, 2, 3, 4}, ID "
        "colours decide among {0, 1, 2, 3, 4}: 5 rotations\n",
        "  1      71.9       10.17        rejected, but composed of accepted shifts      ID "
        "colours\n",
        "  2      144.1      9.93         accepted: residual <= tolerance                ID "
        "colours\n"}) {
    EXPECT_NE(run.out.find(line), std::string::npos) << line << "\n---\n" << run.out;
  }
  // The list agrees with the count.
  const IdsRun list = RunPatlab("ids tests/data/detect/pentagon-irregular.toml --colors 2 --list");
  EXPECT_NE(list.out.find("pentagon-irregular, 2 colours: 6 IDs (slots = patches 1 2 3 4 5)\n"
                          "     0  A A A A B\n"
                          "     1  A A A B B\n"
                          "     2  A A B A B\n"
                          "     3  A A B B B\n"
                          "     4  A B A B B\n"
                          "     5  A B B B B\n"),
            std::string::npos)
      << list.out;
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
            "patlab ids: pattern 'hexagon' not found; expected an existing file or a name "
            "in " PATLAB_SOURCE_DIR "/patterns/\n");
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

// End-to-end tests of `patlab stats`: run the binary, check stdout, stderr and exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int status = -1;
  std::string out;
  std::string err;
};

class StatsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("patlab_stats_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }

  RunResult Run(const std::string& args) {
    const std::string cmd =
        "cd '" + dir_.string() + "' && '" PATLAB_BINARY "' stats " + args + " >out.txt 2>err.txt";
    const int raw = std::system(cmd.c_str());
    RunResult r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = Slurp(dir_ / "out.txt");
    r.err = Slurp(dir_ / "err.txt");
    return r;
  }

  static std::string Slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  fs::path dir_;
};

TEST_F(StatsCli, KsTextOutput) {
  Write("a.txt", "1\n2\n2\n3\n5\n");
  Write("b.txt", "2\n2\n4\n6\n7\n8\n");
  const RunResult r = Run("ks a.txt b.txt");
  EXPECT_EQ(r.status, 0) << r.err;
  // scipy.stats.ks_2samp([1,2,2,3,5],[2,2,4,6,7,8]) = (0.5, 0.35714285714285715)
  EXPECT_EQ(r.out,
            "two-sample Kolmogorov-Smirnov test\n"
            "alternative  two-sided\n"
            "method       exact\n"
            "n1           5\n"
            "n2           6\n"
            "D            0.5\n"
            "D_scaled     0.8257228238447705   (sqrt(n1*n2/(n1+n2)) * D)\n"
            "p_value      0.35714285714285715\n");
  EXPECT_EQ(r.err, "");
}

TEST_F(StatsCli, KsJsonFromCsvColumn) {
  Write("a.csv", "id,err\n1,1\n2,2\n3,2\n4,3\n5,5\n");
  Write("b.csv", "id,err\n1,2\n2,2\n3,4\n4,6\n5,7\n6,8\n");
  const RunResult r = Run("ks a.csv b.csv --column err --alternative greater --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("d").get<double>(), 0.5);
  EXPECT_EQ(j.at("p_value").get<double>(), 0.17965367965367965);  // scipy 1.10
  EXPECT_EQ(j.at("method").get<std::string>(), "exact");
  EXPECT_EQ(j.at("alternative").get<std::string>(), "greater");
}

TEST_F(StatsCli, WilcoxonTextAndJson) {
  Write("x.txt", "11\n8\n13\n14\n15\n");
  Write("y.txt", "10\n10\n10\n10\n10\n");
  RunResult r = Run("wilcoxon x.txt y.txt");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out,
            "Wilcoxon signed-rank test\n"
            "alternative  two-sided\n"
            "method       exact\n"
            "zero_method  wilcox\n"
            "correction   no\n"
            "n            5\n"
            "n_zero       0\n"
            "statistic    2   (min(R+, R-))\n"
            "r_plus       13\n"
            "r_minus      2\n"
            "p_value      0.1875\n");
  r =
      Run("wilcoxon x.txt y.txt --method approx --correction --zero-method pratt "
          "--alternative greater --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("method").get<std::string>(), "approx");
  EXPECT_EQ(j.at("statistic").get<double>(), 13.0);
  // (13 - 7.5 - 0.5) / sqrt(5*6*11/24)
  EXPECT_DOUBLE_EQ(j.at("z").get<double>(), 5.0 / std::sqrt(330.0 / 24.0));
}

TEST_F(StatsCli, SummaryPrintsIntervals) {
  Write("a.txt", "1\n2\n3\n4\n");
  const RunResult r = Run("summary a.txt --format json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_DOUBLE_EQ(j.at("std").get<double>(), std::sqrt(5.0 / 3.0));
  EXPECT_EQ(j.at("n").get<int>(), 4);
}

TEST_F(StatsCli, ErrorsAreClearAndExitWith2) {
  Write("a.txt", "1\n2\n3\n");
  Write("b.txt", "1\n2\n");
  Write("bad.csv", "x,theta\n1,0.5\n2,abc\n");
  Write("nan.txt", "1\nNaN\n");
  Write("inf.txt", "1\n2\ninf\n");
  Write("empty.txt", "# no data\n");
  struct Case {
    std::string args, err;
  };
  const Case cases[] = {
      {"wilcoxon a.txt b.txt",
       "patlab stats: a.txt has 3 values but b.txt has 2; expected paired samples of equal "
       "length\n"},
      {"ks empty.txt a.txt",
       "patlab stats: empty.txt: no numbers found; expected at least one "
       "value\n"},
      {"ks bad.csv bad.csv --column theta",
       "patlab stats: bad.csv:3: cannot read 'abc' in column 'theta' as a number; expected a "
       "decimal number such as 0.52 or -1.5e-3\n"},
      {"ks a.txt nan.txt",
       "patlab stats: nan.txt:2: 'NaN' is not a finite number; expected a "
       "finite number (no NaN or infinity)\n"},
      {"wilcoxon inf.txt a.txt",
       "patlab stats: inf.txt:3: 'inf' is not a finite number; "
       "expected a finite number (no NaN or infinity)\n"},
      {"ks a.txt", "patlab stats: 'ks' takes 2 files, got 1; expected patlab stats ks A B\n"},
      {"ks a.txt b.txt --alternative both",
       "patlab stats: --alternative is \"both\"; expected \"two-sided\", \"less\" or "
       "\"greater\"\n"},
      {"wilcoxon a.txt a.txt --zero-method drop",
       "patlab stats: --zero-method is \"drop\"; expected \"wilcox\", \"pratt\" or "
       "\"zsplit\"\n"},
      {"wilcoxon a.txt a.txt",
       "patlab stats: a.txt and a.txt: every difference is zero, so zero method 'wilcox' leaves "
       "nothing to rank; "
       "expected at least one non-zero difference (or use zsplit)\n"},
      {"anova a.txt",
       "patlab stats: unknown stats test 'anova'; expected ks, wilcoxon or "
       "summary\n"},
      {"ks missing.txt a.txt",
       "patlab stats: missing.txt: cannot open file; expected a readable file of numbers\n"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const RunResult r = Run(c.args);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err, c.err);
  }
}

TEST_F(StatsCli, HelpGoesToStdout) {
  const RunResult r = Run("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("patlab stats ks fast_theta.txt ml_theta.txt"), std::string::npos);
}

}  // namespace

// patlab stats: the statistics of src/patlab/stats/ on columns of numbers read from files.
#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "patlab/core/enum_names.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/numeric_column.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::cli {
namespace {

namespace po = boost::program_options;

constexpr const char* kStatsExamples = R"(examples:
  patlab stats ks fast_theta.txt ml_theta.txt
  patlab stats ks fast.csv ml.csv --column theta_err --alternative less --method exact --format json
  patlab stats wilcoxon abs_err_40mm.txt abs_err_60mm.txt --alternative greater
  patlab stats wilcoxon a.csv b.csv --column x --zero-method zsplit --correction
  patlab stats summary errors.txt --level 0.99

TEST is one of:
  ks A B          two-sample Kolmogorov-Smirnov test (do A and B come from one distribution?)
  wilcoxon A B    Wilcoxon signed-rank test on the pairs (A[i], B[i]), differences A - B
  summary A       mean and standard deviation with confidence intervals

Each FILE holds one number a line ('#' comments and blank lines are skipped), or is a CSV file
with a header row when --column NAME is given (the same column is read from every file).
NaN, infinity, non-numeric cells and empty inputs are errors (file:line), exit status 2.
)";

struct StatsCliOptions {
  std::string test;
  std::vector<std::string> files;
  std::string column;
  std::string alternative = "two-sided";
  std::string method = "auto";
  std::string zero_method = "wilcox";
  bool correction = false;
  double level = 0.95;
  std::string format = "table";
};

void PrintRows(const std::vector<std::pair<std::string, std::string>>& rows) {
  for (const auto& [key, value] : rows) {
    std::string padded = key;
    padded.resize(std::max<std::size_t>(padded.size() + 2, 13), ' ');
    std::cout << padded << value << "\n";
  }
}

std::vector<double> Load(const std::string& path, const StatsCliOptions& options) {
  formats::NumericColumnOptions column;
  column.column = options.column;
  return formats::ReadNumericColumn(path, column);
}

// The statistics library names no file: its messages about the samples get the files they came
// from ("a.txt and b.txt: the KS test needs ...").
template <typename F>
auto OnFiles(const StatsCliOptions& o, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    std::string names;
    for (const std::string& file : o.files) names += (names.empty() ? "" : " and ") + file;
    throw InputError(names + ": " + e.what());
  }
}

void RequireFiles(const StatsCliOptions& o, std::size_t n) {
  if (o.files.size() != n) {
    throw InputError("'" + o.test + "' takes " + std::to_string(n) + (n == 1 ? " file" : " files") +
                     ", got " + std::to_string(o.files.size()) + "; expected patlab stats " +
                     o.test + (n == 1 ? " A" : " A B"));
  }
}

int RunKs(const StatsCliOptions& o) {
  RequireFiles(o, 2);
  stats::KsOptions options;
  options.alternative = ParseName(o.alternative, stats::kAlternativeNames, "--alternative");
  options.method = ParseName(o.method, stats::kKsMethodNames, "--method");
  const std::vector<double> a = Load(o.files[0], o);
  const std::vector<double> b = Load(o.files[1], o);
  const stats::KsResult r = OnFiles(o, [&] { return stats::KsTwoSample(a, b, options); });
  if (o.format == "json") {
    nlohmann::json j = {{"test", "ks"},
                        {"alternative", stats::AlternativeName(options.alternative)},
                        {"method", stats::KsMethodName(r.method_used)},
                        {"n1", r.n1},
                        {"n2", r.n2},
                        {"d", r.d},
                        {"d_scaled", r.d_scaled},
                        {"p_value", r.p_value},
                        {"sign", r.sign},
                        {"location", r.location}};
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "two-sample Kolmogorov-Smirnov test\n";
  PrintRows({{"alternative", std::string(stats::AlternativeName(options.alternative))},
             {"method", std::string(stats::KsMethodName(r.method_used))},
             {"n1", std::to_string(r.n1)},
             {"n2", std::to_string(r.n2)},
             {"D", FormatRoundTrip(r.d)},
             {"D_scaled", FormatRoundTrip(r.d_scaled) + "   (sqrt(n1*n2/(n1+n2)) * D)"},
             {"p_value", FormatRoundTrip(r.p_value)}});
  return kExitOk;
}

int RunWilcoxon(const StatsCliOptions& o) {
  RequireFiles(o, 2);
  stats::WilcoxonOptions options;
  options.alternative = ParseName(o.alternative, stats::kAlternativeNames, "--alternative");
  options.method = ParseName(o.method, stats::kWilcoxonMethodNames, "--method");
  options.zero_method = ParseName(o.zero_method, stats::kZeroMethodNames, "--zero-method");
  options.correction = o.correction;
  const std::vector<double> a = Load(o.files[0], o);
  const std::vector<double> b = Load(o.files[1], o);
  if (a.size() != b.size()) {
    throw InputError(o.files[0] + " has " + std::to_string(a.size()) + " values but " + o.files[1] +
                     " has " + std::to_string(b.size()) +
                     "; expected paired samples of equal length");
  }
  const stats::WilcoxonResult r =
      OnFiles(o, [&] { return stats::WilcoxonSignedRank(a, b, options); });
  if (o.format == "json") {
    nlohmann::json j = {{"test", "wilcoxon"},
                        {"alternative", stats::AlternativeName(options.alternative)},
                        {"method", stats::WilcoxonMethodName(r.method_used)},
                        {"zero_method", stats::ZeroMethodName(options.zero_method)},
                        {"correction", options.correction},
                        {"n", r.n},
                        {"n_zero", r.n_zero},
                        {"statistic", r.statistic},
                        {"r_plus", r.r_plus},
                        {"r_minus", r.r_minus},
                        {"z", r.z},  // NaN (exact method) is written as null
                        {"p_value", r.p_value}};
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "Wilcoxon signed-rank test\n";
  std::vector<std::pair<std::string, std::string>> rows = {
      {"alternative", std::string(stats::AlternativeName(options.alternative))},
      {"method", std::string(stats::WilcoxonMethodName(r.method_used))},
      {"zero_method", std::string(stats::ZeroMethodName(options.zero_method))},
      {"correction", options.correction ? "yes" : "no"},
      {"n", std::to_string(r.n)},
      {"n_zero", std::to_string(r.n_zero)},
      {"statistic",
       FormatRoundTrip(r.statistic) +
           (options.alternative == stats::Alternative::kTwoSided ? "   (min(R+, R-))" : "   (R+)")},
      {"r_plus", FormatRoundTrip(r.r_plus)},
      {"r_minus", FormatRoundTrip(r.r_minus)}};
  if (r.method_used == stats::WilcoxonMethod::kApprox) rows.push_back({"z", FormatRoundTrip(r.z)});
  rows.push_back({"p_value", FormatRoundTrip(r.p_value)});
  PrintRows(rows);
  return kExitOk;
}

int RunSummary(const StatsCliOptions& o) {
  RequireFiles(o, 1);
  if (!(o.level > 0.0 && o.level < 1.0)) {
    throw InputError("--level is " + FormatNumber(o.level) +
                     "; expected a confidence level in (0, 1), e.g. 0.95");
  }
  const std::vector<double> a = Load(o.files[0], o);
  const stats::StdWithCi s = OnFiles(o, [&] { return stats::StdWithConfidence(a, o.level); });
  const stats::MeanWithCi m = OnFiles(o, [&] { return stats::MeanWithConfidence(a, o.level); });
  if (o.format == "json") {
    nlohmann::json j = {{"test", "summary"},     {"n", s.n},
                        {"level", s.level},      {"mean", m.mean},
                        {"mean_lower", m.lower}, {"mean_upper", m.upper},
                        {"std", s.std},          {"std_lower", s.lower},
                        {"std_upper", s.upper}};
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "summary (" << FormatRoundTrip(100 * s.level) << "% confidence intervals)\n";
  PrintRows({{"n", std::to_string(s.n)},
             {"mean", FormatRoundTrip(m.mean) + "   [" + FormatRoundTrip(m.lower) + ", " +
                          FormatRoundTrip(m.upper) + "]"},
             {"std", FormatRoundTrip(s.std) + "   [" + FormatRoundTrip(s.lower) + ", " +
                         FormatRoundTrip(s.upper) + "]"}});
  return kExitOk;
}

// The help's option groups (command_line.h).
const OptionGroups kStatsGroups = {
    {"input", {"column"}},
    {"test", {"alternative", "method", "zero-method", "correction", "level"}}};

int RunStats(const std::vector<std::string>& args) {
  StatsCliOptions o;
  po::options_description visible("usage: patlab stats TEST FILE... [options]\n\noptions");
  // clang-format off
  visible.add_options()
      ("column", po::value(&o.column), "read column NAME of CSV files with a header row")
      ("alternative", po::value(&o.alternative)->default_value(o.alternative),
       "two-sided | less | greater (ks: less = CDF of A below B's somewhere; wilcoxon: less = "
       "A - B tends to be negative)")
      ("method", po::value(&o.method)->default_value(o.method),
       "ks: auto | exact | asymp; wilcoxon: auto | exact | approx")
      ("zero-method", po::value(&o.zero_method)->default_value(o.zero_method),
       "wilcoxon: wilcox | pratt | zsplit (treatment of zero differences)")
      ("correction", po::bool_switch(&o.correction),
       "wilcoxon: continuity correction of the normal approximation")
      ("level", po::value(&o.level)->default_value(o.level, "0.95"),
       "summary: confidence level of the intervals, in (0, 1)")
      ("format", po::value(&o.format)->default_value(o.format), "what stdout gets: table or json");
  // clang-format on
  std::vector<std::string> words;
  po::variables_map vm;
  if (!ParseArguments(args, visible, kStatsGroups, "test", po::value(&words), -1, kStatsExamples,
                      &vm, {{"--json", "--format json"}})) {
    return kExitOk;
  }
  CheckFormat(o.format, "table|json");
  if (words.empty()) {
    throw InputError(
        "missing TEST; expected 'patlab stats ks|wilcoxon|summary FILE...' (see --help)");
  }
  o.test = words[0];
  o.files.assign(words.begin() + 1, words.end());
  if (o.test == "ks") return RunKs(o);
  if (o.test == "wilcoxon") return RunWilcoxon(o);
  if (o.test == "summary") return RunSummary(o);
  throw InputError("unknown stats test '" + o.test + "'; expected ks, wilcoxon or summary");
}

}  // namespace

PATLAB_REGISTER_COMMAND("stats", "KS, Wilcoxon and std/mean confidence intervals on number files",
                        RunStats);

}  // namespace patlab::cli

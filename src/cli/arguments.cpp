#include "cli/arguments.h"

#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli/command_line.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/csv.h"
#include "patlab/sim/runner.h"

namespace patlab::cli {

namespace po = boost::program_options;

namespace {

// "patlab simulate EXPERIMENT [options]" from the options' caption, the first line they print
// ("usage: patlab simulate ...", or "patlab simulate ...:").
std::string UsageOf(const po::options_description& visible) {
  std::ostringstream printed;
  printed << visible;
  std::string usage = printed.str().substr(0, printed.str().find('\n'));
  if (usage.starts_with("usage: ")) usage.erase(0, 7);
  if (usage.ends_with(":")) usage.pop_back();
  return usage;
}

}  // namespace

bool ParseArguments(const std::vector<std::string>& args, const po::options_description& visible,
                    const OptionGroups& groups, const char* positional_name,
                    po::value_semantic* positional, int max_positional, const char* examples,
                    po::variables_map* vm,
                    const std::vector<std::pair<std::string, std::string>>& removed) {
  const std::string usage = UsageOf(visible);
  const size_t name_start = usage.find(' ') + 1;
  const std::string command = usage.substr(name_start, usage.find(' ', name_start) - name_start);
  // The examples text: "examples:" and the example lines, a blank line, then the description.
  std::string text = examples;
  if (text.starts_with("\n")) text.erase(0, 1);
  if (text.starts_with("examples:\n")) text.erase(0, 10);
  const size_t blank = text.find("\n\n");
  CommandHelp help{usage, blank == std::string::npos ? "" : text.substr(blank + 2),
                   blank == std::string::npos ? text : text.substr(0, blank + 1)};
  CommandLine line(command, help);
  line.AddGrouped(visible, groups);
  line.Positional(positional_name, positional, max_positional);
  for (const auto& [flag, replacement] : removed) line.Removed(flag, replacement);
  return line.Parse(args, vm);
}

namespace {

// Splits on commas and parses each item completely with `parse` (std::stod, std::stoi...);
// `accept` checks the value.
template <typename T, typename Parse, typename Accept>
std::vector<T> ParseList(const std::string& text, const std::string& flag,
                         const std::string& expected, Parse parse, Accept accept) {
  std::vector<T> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    T v{};
    try {
      v = parse(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !accept(v)) {
      throw InputError(flag + " has '" + item + "'; expected " + expected);
    }
    values.push_back(v);
  }
  if (values.empty()) throw InputError(flag + " is empty; expected " + expected);
  return values;
}

}  // namespace

std::vector<double> ParseNumberList(const std::string& text, const std::string& flag,
                                    const std::string& expected) {
  return ParseList<double>(
      text, flag, expected,
      [](const std::string& s, size_t* used) {
        const std::optional<double> v = io::ParseDouble(s);  // from_chars: any locale
        *used = v && (std::isfinite(*v) || s.find_first_of("iInN") != s.npos) ? s.size() : 0;
        return v.value_or(0.0);
      },
      [](double) { return true; });
}

std::vector<int> ParseIntegerList(const std::string& text, const std::string& flag, int lo, int hi,
                                  const std::string& expected) {
  return ParseList<int>(
      text, flag, expected, [](const std::string& s, size_t* used) { return std::stoi(s, used); },
      [lo, hi](int v) { return v >= lo && v <= hi; });
}

uint64_t ParseSeed(const std::string& text, const std::string& flag) {
  size_t used = 0;
  uint64_t seed = 0;
  try {
    seed = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || text[0] == '-') {
    throw InputError(flag + " is '" + text + "'; expected an integer >= 0");
  }
  return seed;
}

void CheckThreads(int threads) {
  if (threads < 0 || threads > sim::kMaxThreads) {
    throw InputError("--threads is " + std::to_string(threads) + "; expected 0 (all cores) to " +
                     std::to_string(sim::kMaxThreads));
  }
}

void ThrowFlagProblem(const std::vector<OptionsProblem>& problems, const po::variables_map& vm,
                      const std::vector<std::pair<std::string, std::string>>& names) {
  for (const OptionsProblem& problem : problems) {
    for (const auto& [name, flag] : names) {
      if (vm.count(flag.substr(2)) == 0 || !problem.message.starts_with(name + " ")) continue;
      std::string message = flag;
      message.append(problem.message, name.size());
      throw InputError(message);
    }
  }
}

void ThrowCameraFlagProblem(const render::CameraSensorOptions& sensor,
                            const render::CameraJitter& jitter, const po::variables_map& vm) {
  ThrowFlagProblem(render::Check(sensor), vm,
                   {{"exposure_gain", "--exposure-gain"},
                    {"read_noise_levels", "--read-noise-levels"},
                    {"shot_noise_gain", "--shot-noise-gain"}});
  ThrowFlagProblem(render::Check(jitter), vm,
                   {{"roll_sigma_rad", "--roll-jitter-rad"},
                    {"height_sigma_mm", "--height-jitter-mm"},
                    {"shift_sigma_mm", "--shift-jitter-mm"}});
}

void CheckTolerance(double tolerance_mm) {
  if (!(tolerance_mm >= 0.0) || tolerance_mm > 1e6) {
    throw InputError("--tolerance is " + FormatNumber(tolerance_mm) +
                     "; expected a distance in mm >= 0");
  }
}

std::vector<int> ParseColourCounts(const std::string& text) {
  return ParseIntegerList(text, "--colors", 1, 16,
                          "comma-separated integers from 1 to 16, e.g. 2,3,4");
}

}  // namespace patlab::cli

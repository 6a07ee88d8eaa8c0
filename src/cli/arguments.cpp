#include "cli/arguments.h"

#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/csv.h"

namespace patlab::cli {

namespace po = boost::program_options;

bool ParseArguments(const std::vector<std::string>& args, const po::options_description& visible,
                    const char* positional_name, po::value_semantic* positional, int max_positional,
                    const char* examples, po::variables_map* vm) {
  po::options_description all;
  all.add(visible).add_options()(positional_name, positional);
  po::positional_options_description positionals;
  positionals.add(positional_name, max_positional);
  po::store(po::command_line_parser(args).options(all).positional(positionals).run(), *vm);
  po::notify(*vm);
  if (vm->count("help")) {
    std::cout << visible << "\n" << examples;
    return false;
  }
  return true;
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
  if (threads < 0) throw InputError("--threads is " + std::to_string(threads) + "; expected >= 0");
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

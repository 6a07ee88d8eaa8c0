// Loading tests/data/stats/fixtures.json (written by scripts/stats_fixtures.py with scipy 1.10)
// and regenerating its large inputs bit for bit.
#pragma once

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace patlab::stats::testing {

inline const nlohmann::json& Fixtures() {
  static const nlohmann::json fixtures = [] {
    std::ifstream in(std::string(PATLAB_SOURCE_DIR) + "/tests/data/stats/fixtures.json");
    if (!in) throw std::runtime_error("cannot open tests/data/stats/fixtures.json");
    return nlohmann::json::parse(in);
  }();
  return fixtures;
}

// Mirror of generate() in scripts/stats_fixtures.py: splitmix64 -> 53-bit uniforms, a sum of
// sum_of of them (optionally centred), times a power-of-two scale, plus loc, optionally floored
// to a power-of-two quantum. Every operation is exact or correctly rounded, so the values match.
inline std::vector<double> GenerateSample(const nlohmann::json& spec) {
  std::uint64_t state = spec.at("seed").get<std::uint64_t>();
  const int k = spec.value("sum_of", 1);
  const bool centre = spec.value("centre", false);
  const double scale = spec.value("scale", 1.0);
  const double loc = spec.value("loc", 0.0);
  const double quantum = spec.value("quantum", 0.0);
  std::vector<double> out(spec.at("n").get<std::size_t>());
  for (double& v : out) {
    double s = 0.0;
    for (int i = 0; i < k; ++i) {
      state += 0x9E3779B97F4A7C15ULL;
      std::uint64_t z = state;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
      z ^= z >> 31;
      s += static_cast<double>(z >> 11) * 0x1p-53;
    }
    if (centre) s -= k / 2.0;
    v = loc + scale * s;
    if (quantum != 0.0) v = std::floor(v / quantum) * quantum;
  }
  return out;
}

inline std::vector<double> Sample(const nlohmann::json& input) {
  if (input.contains("gen")) return GenerateSample(input.at("gen"));
  return input.at("values").get<std::vector<double>>();
}

// |actual - expected| <= rel * |expected|, printed with full precision on failure.
#define EXPECT_REL_NEAR(actual, expected, rel)                           \
  EXPECT_LE(std::fabs((actual) - (expected)), (rel)*std::fabs(expected)) \
      << std::setprecision(17) << #actual " = " << (actual) << ", expected " << (expected)

}  // namespace patlab::stats::testing

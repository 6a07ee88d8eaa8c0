#include "patlab/core/options.h"

#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab {

namespace {
std::string WithUnit(std::string expected, std::string_view unit) {
  if (!unit.empty()) expected += " (" + std::string(unit) + ")";
  return expected;
}
}  // namespace

std::string OptionsChecker::Name(std::string_view field) const {
  return table_.empty() ? std::string(field) : table_ + "." + std::string(field);
}

OptionsChecker& OptionsChecker::Require(std::string_view field, double value, bool ok,
                                        std::string_view expected) {
  if (!ok) {
    const std::string name = Name(field);
    problems_.push_back(
        {name, name + " is " + FormatNumber(value) + "; expected " + std::string(expected)});
  }
  return *this;
}

OptionsChecker& OptionsChecker::Positive(std::string_view field, double value,
                                         std::string_view unit) {
  return Require(field, value, std::isfinite(value) && value > 0.0,
                 WithUnit("a finite number > 0", unit));
}

OptionsChecker& OptionsChecker::NonNegative(std::string_view field, double value,
                                            std::string_view unit) {
  return Require(field, value, std::isfinite(value) && value >= 0.0,
                 WithUnit("a finite number >= 0", unit));
}

OptionsChecker& OptionsChecker::InRange(std::string_view field, double value, double lo, double hi,
                                        std::string_view unit) {
  return Require(
      field, value, value >= lo && value <= hi,
      WithUnit("a number in [" + FormatNumber(lo) + ", " + FormatNumber(hi) + "]", unit));
}

OptionsChecker& OptionsChecker::InOpenRange(std::string_view field, double value, double lo,
                                            double hi, std::string_view what) {
  const std::string noun = what.empty() ? std::string("a number") : std::string(what);
  return Require(field, value, value > lo && value < hi,
                 noun + " in (" + FormatNumber(lo) + ", " + FormatNumber(hi) + ")");
}

OptionsChecker& OptionsChecker::IntegerInRange(std::string_view field, int64_t value, int64_t lo,
                                               int64_t hi) {
  if (value < lo || value > hi) {
    const std::string name = Name(field);
    problems_.push_back({name, name + " is " + std::to_string(value) +
                                   "; expected an integer in [" + std::to_string(lo) + ", " +
                                   std::to_string(hi) + "]"});
  }
  return *this;
}

OptionsChecker& OptionsChecker::Fail(std::string_view field, std::string message) {
  problems_.push_back({Name(field), std::move(message)});
  return *this;
}

void ThrowFirstProblem(const std::vector<OptionsProblem>& problems) {
  if (!problems.empty()) throw InputError(problems.front().message);
}

}  // namespace patlab

// Options validation, one idiom for every options struct (docs/architecture.md rule 4; Ceres
// solver.cc OPTION_GE). Each options struct `XOptions` comes with
//
//   std::vector<OptionsProblem> Check(const XOptions& options);  // every broken constraint
//   void Validate(const XOptions& options);  // throws InputError with the first, if any
//
// written with OptionsChecker, one line per field, so each limit is stated once. A problem names
// the field as it is spelled in files and flags ("camera.height_mm") and reads
// "<field> is <value>; expected <constraint>", so a file loader can put it at the key's line
// (io::TomlReader) and every message has the same shape.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace patlab {

struct OptionsProblem {
  std::string field;    // e.g. "max_iterations", "camera.height_mm"
  std::string message;  // e.g. "max_iterations is 0; expected an integer in [1, 1000]"
};

class OptionsChecker {
 public:
  // `table` prefixes field names in messages ("camera" -> "camera.height_mm"); "" for none.
  explicit OptionsChecker(std::string table = "") : table_(std::move(table)) {}

  // value must be finite and > 0. `unit` (e.g. "mm") is appended to the expectation.
  OptionsChecker& Positive(std::string_view field, double value, std::string_view unit = "");
  // value must be finite and >= 0.
  OptionsChecker& NonNegative(std::string_view field, double value, std::string_view unit = "");
  // value must be finite and in [lo, hi].
  OptionsChecker& InRange(std::string_view field, double value, double lo, double hi,
                          std::string_view unit = "");
  // value must be in the open interval (lo, hi), e.g. a probability in (0, 1).
  OptionsChecker& InOpenRange(std::string_view field, double value, double lo, double hi,
                              std::string_view what = "");
  // An integer in [lo, hi].
  OptionsChecker& IntegerInRange(std::string_view field, int64_t value, int64_t lo, int64_t hi);
  // Any other constraint: `ok` false adds "<field> is <value>; expected <expected>".
  OptionsChecker& Require(std::string_view field, double value, bool ok, std::string_view expected);
  // A problem whose message is not of the "<field> is <value>" shape (e.g. an empty list).
  OptionsChecker& Fail(std::string_view field, std::string message);

  // The full field name as messages spell it.
  std::string Name(std::string_view field) const;
  const std::vector<OptionsProblem>& problems() const { return problems_; }
  std::vector<OptionsProblem> Take() { return std::move(problems_); }

 private:
  std::string table_;
  std::vector<OptionsProblem> problems_;
};

// Throws InputError(problems.front().message) when `problems` is not empty.
void ThrowFirstProblem(const std::vector<OptionsProblem>& problems);

}  // namespace patlab

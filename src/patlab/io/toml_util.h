// Helpers for reading our TOML input files with precise, tested error messages. Every error is
// an InputError "file:line: what is wrong; expected what" (docs/architecture.md rule 9).
#pragma once

#include <toml++/toml.h>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/options.h"

namespace patlab::io {

// Parses a TOML file; syntax errors become InputError with the file and line. A missing or
// unreadable file is an InputError too.
toml::table ParseTomlFile(const std::string& path);
// Parses TOML text; `source_name` is used in messages (e.g. a file name).
toml::table ParseTomlText(std::string_view text, const std::string& source_name);
// The whole content of a text file. A missing or unreadable file is an InputError "cannot open
// file; expected a readable <what>", e.g. what = "calibration TOML file".
std::string ReadTextFile(const std::string& path, std::string_view what);
// Input text files (TOML, colors.txt) larger than this are refused before they are read.
inline constexpr uintmax_t kMaxTextFileBytes = 64u << 20;
// Before a file is opened: a directory is "<path>: is a directory; expected a <what>", a file
// over `max_bytes` is "<path>: <size> bytes; expected a <what> of at most <max_bytes> bytes", a
// path that cannot be examined (too long, a symbolic link loop) names the reason. A missing
// file passes: opening it reports that.
void CheckInputFile(const std::string& path, std::string_view what, uintmax_t max_bytes);

// Reads typed values from one TOML table of one file.
class TomlReader {
 public:
  TomlReader(const toml::table& table, std::string file, std::string context = "")
      : table_(table), file_(std::move(file)), context_(std::move(context)) {}

  // Rejects keys not in `allowed` (typos): "unknown key 'radus' in [[patch]] 2; expected one of:
  // x, y, radius, role, colour".
  void CheckKeys(std::initializer_list<std::string_view> allowed) const;

  bool Has(std::string_view key) const { return table_.contains(key); }
  // A finite number (integer or float). `what` says what is expected, e.g. "a number (mm)".
  std::optional<double> OptionalNumber(std::string_view key) const;
  double Number(std::string_view key) const;
  std::optional<std::string> OptionalString(std::string_view key) const;
  std::string String(std::string_view key) const;
  std::optional<int64_t> OptionalInteger(std::string_view key) const;
  std::optional<bool> OptionalBool(std::string_view key) const;

  // The location of `key`'s value, or of the table when the key is absent.
  FileLoc Loc(std::string_view key) const;
  FileLoc TableLoc() const;
  [[noreturn]] void Fail(std::string_view key, const std::string& message) const;
  // "key" or "key in <context>" for messages.
  std::string Describe(std::string_view key) const;

  const toml::table& table() const { return table_; }
  const std::string& file() const { return file_; }

 private:
  const toml::table& table_;
  std::string file_;
  std::string context_;
};

FileLoc LocOf(const std::string& file, const toml::node& node);
// The TOML type name of a node for messages: "a string", "an integer", "a table", ...
std::string TypeName(const toml::node& node);
// Where the option `field` (as OptionsProblem::field names it: "runs", "camera.height_mm") is
// set in the file whose root table is `root`: the line of its value, else the line of the deepest
// table of its path that the file has, else the file's first table.
FileLoc FieldLoc(const toml::table& root, const std::string& file, std::string_view field);
// Throws the first of `problems` (core/options.h), if any, as InputError at its field's line.
void ThrowFirstProblemAt(const toml::table& root, const std::string& file,
                         const std::vector<OptionsProblem>& problems);

}  // namespace patlab::io

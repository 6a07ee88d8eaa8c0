#include "patlab/io/toml_util.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "patlab/core/format.h"

namespace patlab::io {

namespace {

toml::table ParseOrThrow(std::string_view text, const std::string& source_name) {
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw InputError(FileLoc{source_name, static_cast<int>(e.source().begin.line)},
                     "TOML syntax error: " + std::string(e.description()));
  }
}

}  // namespace

toml::table ParseTomlFile(const std::string& path) {
  return ParseOrThrow(ReadTextFile(path, "TOML file"), path);
}

toml::table ParseTomlText(std::string_view text, const std::string& source_name) {
  return ParseOrThrow(text, source_name);
}

std::string ReadTextFile(const std::string& path, std::string_view what) {
  CheckInputFile(path, what, kMaxTextFileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(FileLoc{path, 0},
                     "cannot open file; expected a readable " + std::string(what));
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void CheckInputFile(const std::string& path, std::string_view what, uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    throw InputError(FileLoc{EscapeForMessage(path, 1024), 0},
                     ec.message() + "; expected a readable " + std::string(what));
  }
  if (fs::is_directory(status)) {
    throw InputError(FileLoc{path, 0}, "is a directory; expected a " + std::string(what));
  }
  if (fs::is_regular_file(status)) {
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > max_bytes) {
      throw InputError(FileLoc{path, 0}, std::to_string(size) + " bytes; expected a " +
                                             std::string(what) + " of at most " +
                                             std::to_string(max_bytes) + " bytes");
    }
  }
}

FileLoc LocOf(const std::string& file, const toml::node& node) {
  return FileLoc{file, static_cast<int>(node.source().begin.line)};
}

std::string TypeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return "a date/time";
    default:
      return "nothing";
  }
}

FileLoc FieldLoc(const toml::table& root, const std::string& file, std::string_view field) {
  const toml::table* table = &root;
  while (true) {
    const size_t dot = field.find('.');
    const toml::node* node = table->get(field.substr(0, dot));
    if (node == nullptr) return LocOf(file, *table);
    if (dot == std::string_view::npos) return LocOf(file, *node);
    if (node->as_table() == nullptr) return LocOf(file, *node);
    table = node->as_table();
    field.remove_prefix(dot + 1);
  }
}

void ThrowFirstProblemAt(const toml::table& root, const std::string& file,
                         const std::vector<OptionsProblem>& problems) {
  if (problems.empty()) return;
  throw InputError(FieldLoc(root, file, problems.front().field), problems.front().message);
}

std::string TomlReader::Describe(std::string_view key) const {
  std::string d(key);
  if (!context_.empty()) d += " in " + context_;
  return d;
}

FileLoc TomlReader::TableLoc() const { return LocOf(file_, table_); }

FileLoc TomlReader::Loc(std::string_view key) const {
  if (const toml::node* node = table_.get(key)) return LocOf(file_, *node);
  return TableLoc();
}

void TomlReader::Fail(std::string_view key, const std::string& message) const {
  throw InputError(Loc(key), message);
}

void TomlReader::CheckKeys(std::initializer_list<std::string_view> allowed) const {
  for (const auto& [key, node] : table_) {
    bool known = false;
    for (std::string_view a : allowed) known = known || key.str() == a;
    if (known) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw InputError(LocOf(file_, node), "unknown key '" + std::string(key.str()) + "'" +
                                             (context_.empty() ? "" : " in " + context_) +
                                             "; expected one of: " + list);
  }
}

std::optional<double> TomlReader::OptionalNumber(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  double value;
  if (const auto* i = node->as_integer()) {
    value = static_cast<double>(i->get());
  } else if (const auto* f = node->as_floating_point()) {
    value = f->get();
  } else {
    Fail(key, Describe(key) + " is " + TypeName(*node) + "; expected a number");
  }
  if (!std::isfinite(value)) {
    Fail(key, Describe(key) + " is " + patlab::FormatNumber(value) + "; expected a finite number");
  }
  return value;
}

double TomlReader::Number(std::string_view key) const {
  auto v = OptionalNumber(key);
  if (!v) Fail(key, "missing " + Describe(key) + "; expected a number");
  return *v;
}

std::optional<std::string> TomlReader::OptionalString(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* s = node->as_string();
  if (s == nullptr) Fail(key, Describe(key) + " is " + TypeName(*node) + "; expected a string");
  return s->get();
}

std::string TomlReader::String(std::string_view key) const {
  auto v = OptionalString(key);
  if (!v) Fail(key, "missing " + Describe(key) + "; expected a string");
  return *v;
}

std::optional<int64_t> TomlReader::OptionalInteger(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* i = node->as_integer();
  if (i == nullptr) Fail(key, Describe(key) + " is " + TypeName(*node) + "; expected an integer");
  return i->get();
}

std::optional<bool> TomlReader::OptionalBool(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return std::nullopt;
  const auto* b = node->as_boolean();
  if (b == nullptr)
    Fail(key, Describe(key) + " is " + TypeName(*node) + "; expected true or false");
  return b->get();
}

}  // namespace patlab::io

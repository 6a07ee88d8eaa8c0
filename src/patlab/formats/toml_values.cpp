#include <cmath>
#include <filesystem>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/formats/toml_values_internal.h"

namespace patlab::formats::internal {

namespace {

std::optional<double> FiniteNumber(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point(); f && std::isfinite(f->get())) return f->get();
  return std::nullopt;
}

}  // namespace

std::optional<Vec2> PairOf(const toml::node& node) {
  const toml::array* a = node.as_array();
  if (a == nullptr || a->size() != 2) return std::nullopt;
  const auto x = FiniteNumber((*a)[0]), y = FiniteNumber((*a)[1]);
  if (!x || !y) return std::nullopt;
  return Vec2(*x, *y);
}

Vec2 ReadPair(const io::TomlReader& r, std::string_view key, const std::string& expected) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) r.Fail(key, "missing " + r.Describe(key) + "; expected " + expected);
  const auto pair = PairOf(*node);
  if (!pair) r.Fail(key, r.Describe(key) + " is malformed; expected " + expected);
  return *pair;
}

std::vector<Vec2> ReadPairList(const io::TomlReader& r, std::string_view key,
                               const std::string& expected) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) r.Fail(key, "missing " + r.Describe(key) + "; expected " + expected);
  const toml::array* a = node->as_array();
  if (a == nullptr || a->empty())
    r.Fail(key, r.Describe(key) + " is not a non-empty array; expected " + expected);
  std::vector<Vec2> out;
  for (size_t i = 0; i < a->size(); ++i) {
    const auto pair = PairOf((*a)[i]);
    if (!pair) {
      throw InputError(io::LocOf(r.file(), (*a)[i]), "element " + std::to_string(i + 1) + " of " +
                                                         r.Describe(key) +
                                                         " is malformed; expected " + expected);
    }
    out.push_back(*pair);
  }
  return out;
}

std::vector<const toml::table*> TableArray(const toml::table& root, std::string_view key,
                                           const std::string& file) {
  std::vector<const toml::table*> out;
  const toml::node* node = root.get(key);
  if (node == nullptr) return out;
  const toml::array* a = node->as_array();
  if (a == nullptr) {
    throw InputError(io::LocOf(file, *node), std::string(key) + " is " + io::TypeName(*node) +
                                                 "; expected [[" + std::string(key) + "]] tables");
  }
  for (const toml::node& e : *a) {
    const toml::table* t = e.as_table();
    if (t == nullptr) {
      throw InputError(io::LocOf(file, e), std::string(key) + " holds " + io::TypeName(e) +
                                               "; expected [[" + std::string(key) + "]] tables");
    }
    out.push_back(t);
  }
  return out;
}

std::string ResolveBeside(const std::string& base_dir, const std::string& path) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(base_dir) / path).lexically_normal().string();
}

}  // namespace patlab::formats::internal

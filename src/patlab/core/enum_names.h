// Enum names, one idiom (docs/architecture.md rule 4): each enum that appears in files, flags or
// results has one table of its names next to its declaration,
//
//   enum class KsMethod { kAuto, kExact, kAsymp };
//   inline constexpr EnumNames<KsMethod, 3> kKsMethodNames{{
//       {KsMethod::kAuto, "auto"}, {KsMethod::kExact, "exact"}, {KsMethod::kAsymp, "asymp"}}};
//
// and NameOf / ParseName / NameList serve writing, reading and error messages from that table.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "patlab/core/error.h"

namespace patlab {

template <typename E, size_t N>
struct EnumNames {
  std::array<std::pair<E, std::string_view>, N> entries;
};

// The name of `value`; every enumerator must be in the table (a missing one is a bug).
template <typename E, size_t N>
constexpr std::string_view NameOf(E value, const EnumNames<E, N>& names) {
  for (const auto& [v, name] : names.entries) {
    if (v == value) return name;
  }
  PATLAB_CHECK(false && "enumerator missing from its EnumNames table");
  return {};
}

// The enumerator called `name`, or nullopt.
template <typename E, size_t N>
constexpr std::optional<E> FindName(std::string_view name, const EnumNames<E, N>& names) {
  for (const auto& [v, n] : names.entries) {
    if (n == name) return v;
  }
  return std::nullopt;
}

// "auto", "exact" or "asymp": the names as an error message lists them.
template <typename E, size_t N>
std::string NameList(const EnumNames<E, N>& names) {
  std::string out;
  for (size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on
    // "\"" + std::string(...) here.
    out += '"';
    out += names.entries[i].second;
    out += '"';
  }
  return out;
}

// The enumerator called `name`; otherwise throws InputError
// "<what> is \"<name>\"; expected \"a\", \"b\" or \"c\"".
template <typename E, size_t N>
E ParseName(std::string_view name, const EnumNames<E, N>& names, std::string_view what) {
  if (const auto value = FindName(name, names)) return *value;
  throw InputError(std::string(what) + " is \"" + std::string(name) + "\"; expected " +
                   NameList(names));
}

}  // namespace patlab

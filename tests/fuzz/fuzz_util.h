// Shared by the libFuzzer harnesses: the one outcome a parser may have besides success is
// patlab::InputError (bad input, exit 2). Anything else -- another exception, a crash, a
// sanitizer report, a leak -- is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "patlab/core/error.h"

namespace patlab::fuzz {

inline std::string Text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `parse`, accepting InputError and nothing else.
template <typename F>
void ExpectInputErrorOnly(F&& parse) {
  try {
    parse();
  } catch (const InputError&) {
  }
}

}  // namespace patlab::fuzz

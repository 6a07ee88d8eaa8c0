// The one way tests check an error (docs/architecture.md rule 9; fmt's EXPECT_THROW_MSG): the
// statement must throw patlab::InputError whose message is exactly `message`, word for word.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "patlab/core/error.h"

#define EXPECT_INPUT_ERROR(statement, message)                                  \
  do {                                                                          \
    try {                                                                       \
      statement;                                                                \
      ADD_FAILURE() << "expected InputError: " << (message);                    \
    } catch (const ::patlab::InputError& patlab_expect_error) {                 \
      EXPECT_EQ(std::string(patlab_expect_error.what()), std::string(message)); \
    } catch (const std::exception& patlab_expect_error) {                       \
      ADD_FAILURE() << "expected InputError, got another exception: "           \
                    << patlab_expect_error.what();                              \
    }                                                                           \
  } while (false)

// The same for a message that must start with `prefix` (when the rest names a temporary path).
#define EXPECT_INPUT_ERROR_STARTS_WITH(statement, prefix)                                      \
  do {                                                                                         \
    try {                                                                                      \
      statement;                                                                               \
      ADD_FAILURE() << "expected InputError starting with: " << (prefix);                      \
    } catch (const ::patlab::InputError& patlab_expect_error) {                                \
      EXPECT_EQ(std::string(patlab_expect_error.what()).substr(0, std::string(prefix).size()), \
                std::string(prefix));                                                          \
    }                                                                                          \
  } while (false)

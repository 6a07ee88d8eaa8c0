#include "patlab/stats/hypothesis.h"

#include "patlab/core/error.h"

namespace patlab::stats {

std::string_view AlternativeName(Alternative alternative) {
  switch (alternative) {
    case Alternative::kTwoSided:
      return "two-sided";
    case Alternative::kLess:
      return "less";
    case Alternative::kGreater:
      return "greater";
  }
  return "?";
}

Alternative ParseAlternative(std::string_view name) {
  if (name == "two-sided") return Alternative::kTwoSided;
  if (name == "less") return Alternative::kLess;
  if (name == "greater") return Alternative::kGreater;
  throw InputError("unknown alternative '" + std::string(name) +
                   "'; expected two-sided, less or greater");
}

}  // namespace patlab::stats

// The cases of tests/malformed/malformed_test.cpp: one per way an input is broken, each with
// the files it writes ({dir}: the case's fresh directory, with a trailing '/'; {src}: the source
// tree), the arguments after "patlab", the exit status and the whole message on stderr (without
// the final newline). To review the messages of new cases, run test_malformed with
// PATLAB_MALFORMED_DUMP=DIR: each case's stderr and exit status go to DIR/<name>.err, .code.
// The cases are grouped by input, one header a group.
#pragma once

#include <vector>

#include "malformed_case.h"
#include "malformed_command_cases.h"
#include "malformed_detector_cases.h"
#include "malformed_experiment_cases.h"
#include "malformed_flag_cases.h"
#include "malformed_image_cases.h"
#include "malformed_live_cases.h"
#include "malformed_output_cases.h"
#include "malformed_pattern_cases.h"
#include "malformed_shard_cases.h"

namespace patlab::testing {

// Every group's cases, in the order of the groups.
inline const std::vector<MalformedCase>& MalformedCases() {
  static const std::vector<MalformedCase> cases = [] {
    std::vector<MalformedCase> all;
    for (std::vector<MalformedCase> group :
         {PatternMalformedCases(), DetectorInputMalformedCases(), ImageMalformedCases(),
          ExperimentMalformedCases(), CommandMalformedCases(), LiveMalformedCases(),
          FlagMalformedCases(), OutputAndValueMalformedCases(), ShardMalformedCases()}) {
      all.insert(all.end(), group.begin(), group.end());
    }
    return all;
  }();
  return cases;
}

}  // namespace patlab::testing

// Cases of the malformed-input suite (malformed_cases.h): patlab live's flags and sources. Every
// case sends, if it got so far, to 127.0.0.1 only; none gets so far.
#pragma once

#include <string>
#include <vector>

#include "malformed_case.h"

namespace patlab::testing {

inline std::vector<MalformedCase> LiveMalformedCases() {
  using namespace std::string_literals;
  const std::string golden = "{src}/tests/data/golden/ssl-frame.";
  const std::string files = " -t " + golden + "thresholds.toml -c " + golden +
                            "calibration.toml -s " + golden + "detector.toml";
  return {
      {"LiveSendWithoutPort",
       {},
       "live " + golden + "png" + files + " --send 127.0.0.1",
       2,
       "patlab live: --send is '127.0.0.1'; expected ADDRESS:PORT with a dotted IPv4 address and a port in 1..65535, e.g. 127.0.0.1:10006"s,
       nullptr},
      {"LiveRateUnknown",
       {},
       "live " + golden + "png" + files + " --send 127.0.0.1:9 --rate fast",
       2,
       "patlab live: --rate is \"fast\"; expected \"native\" or \"max\""s,
       nullptr},
      {"LiveCameraIdTwice",
       {},
       "live " + golden + "png " + golden + "png" + files + " --send 127.0.0.1:9 --camera-id 1,1",
       2,
       "patlab live: --camera-id: camera id 1 is given twice; expected one id per camera"s,
       nullptr},
      {"LiveCalibrationMissing",
       {},
       "live " + golden + "png -t " + golden + "thresholds.toml --send 127.0.0.1:9",
       2,
       "patlab live: missing --calibration FILE; expected one for all SOURCEs or one per SOURCE"s,
       nullptr},
      {"LiveVideoNotAVideo",
       {{"bad.mp4", "not a video"s}},
       "live {dir}bad.mp4" + files + " --send 127.0.0.1:9",
       2,
       "patlab live: {dir}bad.mp4: cannot open: Invalid data found when processing input; expected a video file FFmpeg can decode"s,
       nullptr},
  };
}

}  // namespace patlab::testing

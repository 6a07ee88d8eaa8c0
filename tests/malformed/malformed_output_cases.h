// Cases of the malformed-input suite (malformed_cases.h): names that would break an output
// (separators, control characters, invalid UTF-8), output locations (a debug folder that is an
// output file, a result path that is a directory, a full disk, an unwritable --out checked before
// the work), empty frame lists, patterns given to compare, colors.txt and thresholds values, and
// images whose header claims more than the pixel budget.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "malformed_case.h"

namespace patlab::testing {

// A write that fails as on a full disk: files are limited to 2 blocks (ulimit -f) and the signal
// of a write past the limit is ignored, so write() fails with EFBIG.
inline constexpr const char* kFullDisk = "trap '' XFSZ; ulimit -f 2;";

inline std::vector<MalformedCase> OutputAndValueMalformedCases() {
  using namespace std::string_literals;
  return {
      {"CliCompareSigmaNan",
       {},
       "compare butterfly --format json --sigma nan",
       2,
       "patlab compare: --sigma is nan; expected a patch std in mm > 0"s,
       nullptr},
      {"CliCompareSigmaNegative",
       {},
       "compare butterfly --format json --sigma -1",
       2,
       "patlab compare: --sigma is -1; expected a patch std in mm > 0"s,
       nullptr},
      {"CliCompareTrialsHuge",
       {},
       "compare butterfly --format json --trials 1e12",
       2,
       "patlab compare: the argument ('1e12') for option '--trials' is invalid; expected the options and values that 'patlab compare --help' lists"s,
       nullptr},
      {"CliCompareTrialsZero",
       {},
       "compare butterfly --format json --trials 0",
       2,
       "patlab compare: --trials is 0; expected an integer in [2, 1000000000]"s,
       nullptr},
      {"CliCompareFramesNegative",
       {},
       "compare butterfly --format json --frames -3",
       2,
       "patlab compare: --frames is -3; expected an integer in [1, 100000000]"s,
       nullptr},
      {"CliCompareIdColorsNine",
       {},
       "compare butterfly --format json --id-colors 9",
       2,
       "patlab compare: --id-colors is 9; expected an integer in [1, 8]"s,
       nullptr},
      {"CliCompareToleranceNan",
       {},
       "compare butterfly --format json --tolerance nan",
       2,
       "patlab compare: --tolerance is nan; expected a distance in mm >= 0"s,
       nullptr},
      {"CliSimulateNameNewline",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml -q --out {dir}out --name \"$(printf 'a\\nb')\"",
       2,
       "patlab simulate: --name is 'a\\x0ab'; expected a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"CliSimulateNameBackslash",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml -q --out {dir}out --name 'a\\\\b'",
       2,
       "patlab simulate: --name is 'a\\\\b'; expected a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"CliSimulateNameNul",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml -q --out {dir}out --name \"$(printf 'a\\001b')\"",
       2,
       "patlab simulate: --name is 'a\\x01b'; expected a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"CliSimulateNameTooLong",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml -q --out {dir}out --name "
       "nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn"
       "nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn"
       "nnnnnnnnnnnnnnnnnnn",
       2,
       "patlab simulate: --name is 'nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn... (201 bytes)'; expected a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"CliAnalyzeNameSlash",
       {{"t.csv", "frame,subject,run,x_mm,y_mm,theta_rad\n0,0,1,0,0,0\n1,0,1,1,1,0\n"s}},
       "analyze {dir}t.csv -q --out {dir}out --name sub/x",
       2,
       "patlab analyze: --name is 'sub/x'; expected a non-empty file base name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"CliOutNotUtf8",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml -q --out \"$(printf '{dir}o\\377')\"",
       2,
       "patlab simulate: argument 4 '{dir}o\\xff' is not valid UTF-8; expected UTF-8 text (rename the file)"s,
       nullptr},
      {"CliSimulateTwoExperiments",
       {{"e.toml",
         "name = \"e\"\npatterns_dir = \"{src}/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = 1\n[sigma]\nvalues = [1]\n"s}},
       "simulate {dir}e.toml {dir}e.toml -q --out {dir}out",
       2,
       "patlab simulate: too many positional options have been specified on the command line; expected the options and values that 'patlab simulate --help' lists"s,
       nullptr},
      {"CliReproduceOutUnderAFile",
       {{"f", "x"s}},
       "reproduce --root {src} --no-figures -q --out {dir}f/out",
       1,
       "patlab reproduce: {dir}f/out/fig5.csv: cannot write: {dir}f is not a directory; expected a writable location"s,
       nullptr},
      {"CliDetectDebugIsTheOutputFile",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q --debug "
       "{dir}out/detections.csv",
       2,
       "patlab detect: --debug {dir}out/detections.csv is the output file {dir}out/detections.csv; expected a debug directory apart from the output files"s,
       nullptr},
      {"CliDetectDebugIsTheTrackFile",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml -s "
       "{src}/tests/data/golden/ssl-frame.detector.toml --out {dir}out -q --track --debug "
       "{dir}out/track.csv",
       2,
       "patlab detect: --debug {dir}out/track.csv is the output file {dir}out/track.csv; expected a debug directory apart from the output files"s,
       nullptr},
      {"CliDetectDebugIsAFile",
       {{"dbg", "x"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q --debug {dir}dbg",
       1,
       "patlab detect: {dir}dbg: cannot write: it is a file; expected a directory for the debug images"s,
       nullptr},
      {"CliDetectEmptyFrameList",
       {{"l.txt", ""s}},
       "detect {dir}l.txt -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}l.txt: names no frame (empty, or only comments and blank lines); expected one frame file a line"s,
       nullptr},
      {"CliDetectCommentOnlyFrameList",
       {{"l.txt", "# nothing here\n\n"s}},
       "detect {dir}l.txt -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}l.txt: names no frame (empty, or only comments and blank lines); expected one frame file a line"s,
       nullptr},
      {"CliCompareBadPattern",
       {{"p.toml", "name = \"p\"\n[[patch]]\nx_mm = 0\n"s}},
       "compare butterfly {dir}p.toml --format json",
       2,
       "patlab compare: {dir}p.toml:3: unknown key 'x_mm' in [[patch]] 0; expected one of: x, y, radius, role, colour, shape, size, angle_deg"s,
       nullptr},
      {"CliCompareMissingPattern",
       {},
       "compare butterfly {dir}nothing.toml --format json",
       2,
       "patlab compare: {dir}nothing.toml: cannot open file; expected a readable TOML file"s,
       nullptr},
      {"ColorsTxtDuplicateAfterNormalisation",
       {{"colors.txt",
         "[Colors]\n(0,0,255) 0.5 1 Dark_Blue\n(0,0,200) 0.5 1 dark blue\n[Thresholds]\n(0:255,0:255,0:255)\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:3: colour 'dark-blue' listed twice (names that differ only in case, spaces, hyphens or underscores, or are aliases, are one colour); expected distinct colours"s,
       nullptr},
      {"ColorsTxtDuplicateAlias",
       {{"colors.txt",
         "[Colors]\n(255,0,255) 0.5 1 pink\n(255,0,200) 0.5 1 Magenta\n[Thresholds]\n(0:255,0:255,0:255)\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:3: colour 'pink' listed twice (names that differ only in case, spaces, hyphens or underscores, or are aliases, are one colour); expected distinct colours"s,
       nullptr},
      {"ColorsTxtMergeNan",
       {{"colors.txt", "[Colors]\n(255,0,255) nan 1 pink\n[Thresholds]\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:2: merge is nan; expected a density in [0, 1]"s,
       nullptr},
      {"ColorsTxtMergeInfinite",
       {{"colors.txt", "[Colors]\n(255,0,255) inf 1 pink\n[Thresholds]\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:2: merge is inf; expected a density in [0, 1]"s,
       nullptr},
      {"ColorsTxtMergeAboveOne",
       {{"colors.txt", "[Colors]\n(255,0,255) 1.5 1 pink\n[Thresholds]\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:2: merge is 1.5; expected a density in [0, 1]"s,
       nullptr},
      {"ColorsTxtMergeNegative",
       {{"colors.txt", "[Colors]\n(255,0,255) -0.2 1 pink\n[Thresholds]\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:2: merge is -0.2; expected a density in [0, 1]"s,
       nullptr},
      {"ColorsTxtExpectedNumHuge",
       {{"colors.txt",
         "[Colors]\n(255,0,255) 0.5 99999999999 pink\n[Thresholds]\n(0:255,0:255,0:255)\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}colors.txt -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}colors.txt:2: expected_num is 99999999999; expected an integer in [0, 1000000]"s,
       nullptr},
      {"ThresholdsMergeAboveOne",
       {{"t.toml", "[[class]]\nname = \"pink\"\nmerge = 3.0\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:3: merge in [[class]] 1 is 3; expected a density in [0, 1]"s,
       nullptr},
      {"ThresholdsMergeNan",
       {{"t.toml", "[[class]]\nname = \"pink\"\nmerge = nan\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:3: merge in [[class]] 1 is nan; expected a finite number"s,
       nullptr},
      {"ThresholdsExpectedNumNegative",
       {{"t.toml", "[[class]]\nname = \"pink\"\nexpected_num = -1\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:3: expected_num in [[class]] 1 is -1; expected an integer in [0, 1000000]"s,
       nullptr},
      {"ThresholdsMinAreaHuge",
       {{"t.toml", "[[class]]\nname = \"pink\"\nmin_area_px = 99999999999\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:3: min_area_px 99999999999 in [[class]] 1; expected 0..268435456 pixels"s,
       nullptr},
      {"ThresholdsClassNameComma",
       {{"t.toml", "[[class]]\nname = \"pi,nk\"\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:2: unknown colour 'pi,nk'; expected a colour of settings/colours.toml (did you mean 'pink'?)"s,
       nullptr},
      {"ThresholdsClassNameNewline",
       {{"t.toml", "[[class]]\nname = \"pi\\nnk\"\n"s}},
       "detect {src}/tests/data/golden/ssl-frame.png -t {dir}t.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}t.toml:2: name 'pi\\x0ank' holds a control character or NUL; expected a non-empty name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL"s,
       nullptr},
      {"ImagePpmClaims100000Square",
       {{"f.ppm", "P6\n100000 100000\n255\nabc"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.ppm: image size 100000x100000; expected 1 to 268435456 pixels"s,
       nullptr},
      {"ImagePpmWidthBeyondParse",
       {{"f.ppm", "P6\n99999999999 2\n255\nabc"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.ppm: byte 3: PPM width too large; expected at most 1000000000"s,
       nullptr},
      {"ImagePpmWidthZero",
       {{"f.ppm", "P6\n0 2\n255\nabc"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.ppm: image size 0x2; expected 1 to 268435456 pixels"s,
       nullptr},
      {"CliDetectDebugImageOnAFullDisk",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q --debug {dir}dbg",
       1,
       "patlab detect: {dir}dbg/ssl-frame.2_colour_lookup.png: cannot write: File too large; expected a writable location"s,
       [](const std::string& dir) { std::filesystem::create_directories(dir + "dbg"); },
       kFullDisk},
      {"CliDetectResultsOnAFullDisk",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       1,
       "patlab detect: {dir}out/detections.csv: cannot write: File too large; expected a writable location"s,
       [](const std::string& dir) { std::filesystem::create_directories(dir + "out"); },
       kFullDisk},
      {"CliSimulateNewOutFolderOnAFullDisk",  // the folders it made are removed again
       {},
       "simulate {src}/experiments/fig5.toml --trials 200 --sigmas 1 -q --out {dir}new/deep",
       1,
       "patlab simulate: {dir}new/deep/fig5.csv: cannot write: File too large; expected a writable location"s,
       nullptr,
       kFullDisk},
      {"CliDetectOutputCsvIsADirectory",
       {},
       "detect {src}/tests/data/golden/ssl-frame.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       1,
       "patlab detect: {dir}out/detections.csv: cannot write: it is a directory; expected a writable location"s,
       [](const std::string& dir) {
         std::filesystem::create_directories(dir + "out/detections.csv");
       }},
      {"ImageJpegClaimsTooManyPixels",
       {},
       "detect {dir}f.jpg -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.jpg: image size 65500x65500; expected 1 to 268435456 pixels"s,
       [](const std::string& dir) { WriteBytes(dir + "f.jpg", JpegClaiming(65500, 65500)); }},
      {"ImageJpegClaimsMoreThanItsBytesHold",
       {},
       "detect {dir}f.jpg -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{dir}c.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.jpg: byte 0: corrupt or truncated JPEG (libjpeg: image size 16384x16384 cannot be coded in 543 bytes, at most 2048 pixels a byte); expected a complete JPEG image"s,
       [](const std::string& dir) {
         WriteBytes(dir + "f.jpg", JpegClaiming(16384, 16384));
         SizedCalibration(dir, 16384, 16384);  // past the header check to the decoder
       }},
      // A frame whose header states another size than the calibration's is refused from its
      // header: its pixel data is broken (a decoder would say so), so the message shows that
      // nothing was decoded.
      {"ImagePngSizeDiffersFromCalibration",
       {},
       "detect {dir}f.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.png: image is 64x48; expected 640x480 as in {src}/tests/data/golden/ssl-frame.calibration.toml"s,
       [](const std::string& dir) { WriteBytes(dir + "f.png", PngClaiming(64, 48)); }},
      {"ImageJpegSizeDiffersFromCalibration",
       {},
       "detect {dir}f.jpg -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.jpg: image is 1000x700; expected 640x480 as in {src}/tests/data/golden/ssl-frame.calibration.toml"s,
       [](const std::string& dir) { WriteBytes(dir + "f.jpg", JpegClaiming(1000, 700)); }},
      {"ImagePpmSizeDiffersFromCalibration",
       {{"f.ppm", "P6\n# a comment\n641 480\n255\nabc"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q",
       2,
       "patlab detect: {dir}f.ppm: image is 641x480; expected 640x480 as in {src}/tests/data/golden/ssl-frame.calibration.toml"s,
       nullptr},
      {"ImageRawSizeDiffersFromCalibration",
       {{"f.yuv", "abcdefghij"s}},
       "detect {dir}f.yuv -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out -q --raw-size 640x482",
       2,
       "patlab detect: {dir}f.yuv: image is 640x482; expected 640x480 as in {src}/tests/data/golden/ssl-frame.calibration.toml"s,
       nullptr},
      {"RenderRobotOutsideField",
       {{"s.toml",
         "calibration = \"{src}/settings/ssl-frame.calibration.toml\"\npattern = "
         "\"{src}/patterns/ssl-standard.toml\"\ncodebook = "
         "\"{src}/patterns/ssl-standard.codebook.toml\"\n[colours]\nfield = [40, 100, 50]\nbody = "
         "[30, 30, 34]\nblue = [35, 75, 210]\npink = [240, 95, 185]\ngreen = [70, 215, "
         "95]\n[[robot]]\nteam = \"blue\"\nid = 0\nx_mm = 4000.0\ny_mm = 0.0\ntheta_rad = 0.3\n"s}},
       "render {dir}s.toml -o {dir}out",
       2,
       "patlab render: {dir}s.toml:13: robot at (4000, 0) mm is outside the field the camera sees (pixel (973, 262), the frame is 640x480); expected a robot whose centre is inside the rendered frame"s,
       nullptr},
  };
}

}  // namespace patlab::testing

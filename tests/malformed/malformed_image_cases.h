// Cases of the malformed-input suite (malformed_cases.h): frame files and frame lists: PNG, PPM,
// JPEG, raw UYVY, folders and list files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "malformed_case.h"

namespace patlab::testing {

inline std::vector<MalformedCase> ImageMalformedCases() {
  namespace fs = std::filesystem;
  using namespace std::string_literals;
  return {
      {"ImagePngTruncated",
       {},
       "detect {dir}f.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.png: byte 100: truncated PNG: chunk 'IDAT' at byte 46 needs 8204 bytes but the file ends after 54; expected a complete PNG file"s,
       [](const std::string& dir) {
         CopyPrefix(PATLAB_SOURCE_DIR "/tests/data/golden/ssl-frame.png", dir + "f.png", 100);
       }},
      {"ImagePngClaimsHugeSize",
       {},
       "detect {dir}f.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{dir}c.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.png: byte 67: truncated or corrupt PNG: 16384x16384 needs 805322752 bytes of pixel data but its 10 bytes of compressed data can hold at most 11000; expected a complete PNG file"s,
       [](const std::string& dir) {
         WriteBytes(dir + "f.png", PngClaiming(16384, 16384));
         SizedCalibration(dir, 16384, 16384);  // past the header check to the decoder
       }},
      {"ImagePngClaimsTooManyPixels",
       {},
       "detect {dir}f.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.png: image size 100000x100000; expected 1 to 268435456 pixels"s,
       [](const std::string& dir) { WriteBytes(dir + "f.png", PngClaiming(100000, 100000)); }},
      {"ImagePpmHugeHeader",
       {{"f.ppm", "P6\n20000 20000\n255\nabc"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.ppm: image size 20000x20000; expected 1 to 268435456 pixels"s,
       nullptr},
      {"ImagePpmMaxval16Bit",
       {{"f.ppm", "P6\n2 2\n65535\nxxxxxxxxxxxxxxxxxxxxxxxx"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{dir}c.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.ppm: byte 7: PPM maxval 65535; expected 255 (8 bits per sample)"s,
       [](const std::string& dir) { SizedCalibration(dir, 2, 2); }},
      {"ImagePpmTruncated",
       {{"f.ppm", "P6\n4 4\n255\nxxxxxxxxxx"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{dir}c.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.ppm: byte 21: truncated PPM: 4x4 needs 48 bytes of pixels from byte 11; expected a file of 59 bytes"s,
       [](const std::string& dir) { SizedCalibration(dir, 4, 4); }},
      {"ImagePpmBadHeader",
       {{"f.ppm", "P6\nfour 4\n255\n"s}},
       "detect {dir}f.ppm -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.ppm: byte 3: bad PPM header: unexpected character; expected the width (a decimal number)"s,
       nullptr},
      {"ImageJpegTruncated",
       {},
       "detect {dir}f.jpg -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.jpg: byte 10: corrupt or truncated JPEG (libjpeg: Premature end of JPEG file); expected a complete JPEG image"s,
       [](const std::string& dir) {
         WriteBytes(dir + "f.jpg", std::string("\xff\xd8\xff\xe0\x00\x10JFIF", 10));
       }},
      {"ImageUnknownFormat",
       {{"f.png", "this is text, not an image\n"s}},
       "detect {dir}f.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.png: byte 0: unknown image format; expected a PNG, JPEG or binary PPM (P6) file"s,
       nullptr},
      {"ImageEmptyDirectory",
       {},
       "detect {dir}frames -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}frames: no frames in directory; expected files ending in .png, .jpg, .jpeg, .ppm, .yuv, .uyvy or .raw"s,
       [](const std::string& dir) { fs::create_directory(dir + "frames"); }},
      {"ImageYuvWithoutSize",
       {{"f.yuv", "abcd"s}},
       "detect {dir}f.yuv -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}f.yuv: a raw YUV frame has no header; expected --raw-size WIDTHxHEIGHT"s,
       nullptr},
      {"ImageYuvWrongSize",
       {{"f.yuv", "abcdefghij"s}},
       "detect {dir}f.yuv -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{dir}c.toml --out {dir}out/d.csv --raw-size 4x4",
       2,
       "patlab detect: {dir}f.yuv: 10 bytes; expected 32 bytes for a 4x4 UYVY frame (width x height x 2)"s,
       [](const std::string& dir) { SizedCalibration(dir, 4, 4); }},
      {"ImageRawSizeOdd",
       {{"f.yuv", "abcd"s}},
       "detect {dir}f.yuv -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv "
       "--raw-size 3x4",
       2,
       "patlab detect: raw frame size 3x4; expected a positive even width and a positive height"s,
       nullptr},
      {"ImageListNamesMissingFrame",
       {{"l.txt", "missing.png\n"s}},
       "detect {dir}l.txt -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}l.txt:1: frame '{dir}missing.png' not found; expected a frame file, one a line"s,
       nullptr},
      {"ImageMissing",
       {},
       "detect {dir}missing.png -t {src}/tests/data/golden/ssl-frame.thresholds.toml "
       "-c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}missing.png: no such file or directory; expected a frame, a directory of frames or a list file"s,
       nullptr},
      {"ImageSymlinkLoop",
       {},
       "detect {dir}A -t {src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}A: Too many levels of symbolic links; expected a path without a symbolic link loop"s,
       [](const std::string& dir) {
         fs::create_symlink(dir + "B", dir + "A");
         fs::create_symlink(dir + "A", dir + "B");
       }},
      {"ImagePathTooLong",
       {},
       "detect "
       "{dir}"
       "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
       "aaaaaaaaaaaa"
       "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
       "aaaaaaaaaaaa"
       "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
       "aaaaaaaaaaaa"
       "aaaaaaaaaaaaaaaaaaaaaaaaaaa.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv",
       2,
       "patlab detect: {dir}aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa.png: File name too long; expected a path whose every component is at most 255 bytes"s,
       nullptr},
      {"ImageDebugNamesCollide",
       {},
       "detect {dir}a/f.png {dir}b/f.png -t "
       "{src}/tests/data/golden/ssl-frame.thresholds.toml -c "
       "{src}/tests/data/golden/ssl-frame.calibration.toml --out {dir}out/d.csv "
       "--debug {dir}debug",
       2,
       "patlab detect: --debug: frames {dir}a/f.png and {dir}b/f.png have the same name 'f'; expected frames with distinct file names (their debug images are named after them)"s,
       [](const std::string& dir) {
         fs::create_directories(dir + "a");
         fs::create_directories(dir + "b");
         fs::copy_file(PATLAB_SOURCE_DIR "/tests/data/golden/ssl-frame.png", dir + "a/f.png");
         fs::copy_file(PATLAB_SOURCE_DIR "/tests/data/golden/ssl-frame.png", dir + "b/f.png");
       }},
  };
}

}  // namespace patlab::testing

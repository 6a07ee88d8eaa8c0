// A case of the malformed-input suite (tests/malformed/malformed_test.cpp) and the helpers its
// set-up functions use. The cases themselves are in malformed_cases.h and the headers it
// includes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace patlab::testing {

struct MalformedCase {
  const char* name;
  std::vector<std::pair<std::string, std::string>> files;
  std::string arguments;
  int exit_code;
  std::string message;
  void (*setup)(const std::string& dir) = nullptr;
  // Shell commands run before patlab in the case's shell, e.g. a file size limit that makes a
  // write fail as on a full disk ("trap '' XFSZ; ulimit -f 2;").
  const char* shell_prefix = nullptr;
};

// gtest prints a case by its name (ctest lists the tests by it).
inline void PrintTo(const MalformedCase& c, std::ostream* os) { *os << c.name; }

inline void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

inline void CopyPrefix(const std::string& from, const std::string& to, size_t n) {
  std::ifstream in(from, std::ios::binary);
  std::string bytes(n, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  WriteBytes(to, bytes);
}

// The golden frame's calibration with another image size, as {dir}c.toml: a frame of that size
// passes detect's header check and reaches its decoder.
inline void SizedCalibration(const std::string& dir, int width_px, int height_px) {
  std::ifstream in(PATLAB_SOURCE_DIR "/tests/data/golden/ssl-frame.calibration.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string size = "image_size_px = [640, 480]";
  text.replace(
      text.find(size), size.size(),
      "image_size_px = [" + std::to_string(width_px) + ", " + std::to_string(height_px) + "]");
  WriteBytes(dir + "c.toml", text);
}

// A PNG whose header claims width x height RGB pixels but whose IDAT holds 10 bytes (CRCs are
// not checked before the size is).
inline std::string PngClaiming(uint32_t width, uint32_t height) {
  const auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  const auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(static_cast<uint32_t>(data.size())) + type + data + be32(0);
  };
  const std::string ihdr = be32(width) + be32(height) + std::string("\x08\x02\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) +
         chunk("IDAT", std::string(10, '\0')) + chunk("IEND", "");
}

// A JPEG whose SOF0 header claims width x height: the small JPEG seed of the image fuzzer with its
// frame size patched (the sizes are checked before any scanline is decoded).
inline std::string JpegClaiming(uint16_t width, uint16_t height) {
  std::ifstream in(PATLAB_SOURCE_DIR "/tests/fuzz/corpus/image/python.jpg", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t sof = bytes.find("\xff\xc0");
  if (sof == std::string::npos || sof + 9 > bytes.size()) return "";
  bytes[sof + 5] = static_cast<char>(height >> 8);
  bytes[sof + 6] = static_cast<char>(height & 0xff);
  bytes[sof + 7] = static_cast<char>(width >> 8);
  bytes[sof + 8] = static_cast<char>(width & 0xff);
  return bytes;
}

}  // namespace patlab::testing

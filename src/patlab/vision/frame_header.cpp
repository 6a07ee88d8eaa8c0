// A frame's size from its header, read before its pixels are decoded (frame_io.h,
// ReadFrameHeaderSize): PNG's IHDR, a JPEG's SOF segment, a binary PPM's width and height, a raw
// UYVY frame's --raw-size.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {

namespace {

namespace fs = std::filesystem;

// Enough for the SOF segment of a JPEG behind its APP segments (EXIF, ICC: 64 KiB each at most,
// a few of them); a header further in is left to the decoder.
constexpr size_t kHeaderBytes = size_t{1} << 20;

std::vector<uint8_t> Head(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return {};
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> head(kHeaderBytes);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

long long BigEndian(const std::vector<uint8_t>& b, size_t at, int bytes) {
  long long v = 0;
  for (int k = 0; k < bytes; ++k) v = (v << 8) | b[at + static_cast<size_t>(k)];
  return v;
}

struct Size {
  long long width = 0, height = 0;
};

// The IHDR chunk, the first after the 8-byte signature: length 13, "IHDR", width, height.
std::optional<Size> PngSize(const std::vector<uint8_t>& b) {
  if (b.size() < 24 || BigEndian(b, 8, 4) != 13 ||
      std::string(b.begin() + 12, b.begin() + 16) != "IHDR") {
    return std::nullopt;
  }
  return Size{BigEndian(b, 16, 4), BigEndian(b, 20, 4)};
}

// The first start-of-frame segment (SOF0 to SOF15 but DHT, JPG and DAC): after its length and
// precision, the height and the width. The walk stops at the start of the scan.
std::optional<Size> JpegSize(const std::vector<uint8_t>& b) {
  size_t at = 2;  // after SOI
  while (at + 4 <= b.size()) {
    if (b[at] != 0xff) return std::nullopt;
    const uint8_t marker = b[at + 1];
    if (marker == 0xff) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) {  // no length
      at += 2;
      continue;
    }
    if (marker == 0xda || marker == 0xd9) return std::nullopt;  // scan or end before any frame
    const size_t length = static_cast<size_t>(BigEndian(b, at + 2, 2));
    const bool frame =
        marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (frame) {
      if (at + 9 > b.size() || length < 7) return std::nullopt;
      return Size{BigEndian(b, at + 7, 2), BigEndian(b, at + 5, 2)};
    }
    if (length < 2) return std::nullopt;
    at += 2 + length;
  }
  return std::nullopt;
}

// "P6", then the width and the height, decimal, after white space and '#' comments.
std::optional<Size> PpmSize(const std::vector<uint8_t>& b) {
  size_t at = 2;
  long long numbers[2] = {0, 0};
  for (long long& n : numbers) {
    while (at < b.size() &&
           (b[at] == '#' || b[at] == ' ' || b[at] == '\t' || b[at] == '\n' || b[at] == '\r')) {
      if (b[at] == '#') {
        while (at < b.size() && b[at] != '\n') ++at;
      } else {
        ++at;
      }
    }
    const size_t start = at;
    while (at < b.size() && b[at] >= '0' && b[at] <= '9') {
      n = n * 10 + (b[at++] - '0');
      if (n > 1'000'000'000) return std::nullopt;  // the decoder names the byte
    }
    if (at == start) return std::nullopt;
  }
  return Size{numbers[0], numbers[1]};
}

}  // namespace

std::optional<FrameHeaderSize> ReadFrameHeaderSize(const std::string& path, int raw_width_px,
                                                   int raw_height_px) {
  std::optional<Size> size;
  if (raw_width_px > 0 && IsRawFrameFile(path)) {
    size = Size{raw_width_px, raw_height_px};
  } else if (const std::vector<uint8_t> b = Head(path);
             b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') {
    size = PngSize(b);
  } else if (b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff) {
    size = JpegSize(b);
  } else if (b.size() >= 2 && b[0] == 'P' && b[1] == '6') {
    size = PpmSize(b);
  }
  if (!size) return std::nullopt;
  // Each side first: the product of two 32-bit header fields can overflow.
  if (size->width <= 0 || size->height <= 0 || size->width > kMaxFramePixels ||
      size->height > kMaxFramePixels || size->width * size->height > kMaxFramePixels) {
    throw InputError(path + ": image size " + std::to_string(size->width) + "x" +
                     std::to_string(size->height) + "; expected 1 to " +
                     std::to_string(kMaxFramePixels) + " pixels");
  }
  return FrameHeaderSize{static_cast<int>(size->width), static_cast<int>(size->height)};
}

}  // namespace patlab::vision

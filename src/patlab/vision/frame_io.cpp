#include "patlab/vision/frame_io.h"

#include <jerror.h>
#include <jpeglib.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_io_internal.h"

namespace patlab::vision {

namespace fs = std::filesystem;

namespace {

// Guards against a corrupt header asking for gigabytes.
constexpr long long kMaxPixels = kMaxFramePixels;

[[noreturn]] void FailAt(const std::string& name, size_t byte, const std::string& message) {
  throw InputError(name + ": byte " + std::to_string(byte) + ": " + message);
}

void CheckSize(const std::string& name, long long width, long long height) {
  // Each side first: the product of two 32-bit header fields can overflow (found by image_fuzz).
  if (width <= 0 || height <= 0 || width > kMaxPixels || height > kMaxPixels ||
      width * height > kMaxPixels) {
    throw InputError(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     "; expected 1 to " + std::to_string(kMaxPixels) + " pixels");
  }
}

uint32_t ReadBigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

// Deflate cannot expand data by more than about 1032:1 (RFC 1951: a 258-byte match costs at
// least 2 bits); 1100 leaves a margin.
constexpr long long kMaxDeflateRatio = 1100;

// The pixel data a PNG header promises cannot come out of `idat_bytes` of compressed data: a
// 100-byte file claiming 16384x16384 is rejected before any pixel memory is allocated.
void CheckPngDataSize(const std::vector<uint8_t>& bytes, const std::string& name,
                      long long idat_bytes) {
  if (bytes.size() < 33) return;  // no IHDR: libpng reports it
  const long long width = ReadBigEndian32(&bytes[16]), height = ReadBigEndian32(&bytes[20]);
  CheckSize(name, width, height);
  const int depth = bytes[24], colour_type = bytes[25];
  const int channels = colour_type == 2 ? 3 : colour_type == 4 ? 2 : colour_type == 6 ? 4 : 1;
  const long long row_bytes = (width * channels * depth + 7) / 8 + 1;
  const long long raw = row_bytes * height;
  if (raw > idat_bytes * kMaxDeflateRatio) {
    FailAt(name, bytes.size(),
           "truncated or corrupt PNG: " + std::to_string(width) + "x" + std::to_string(height) +
               " needs " + std::to_string(raw) + " bytes of pixel data but its " +
               std::to_string(idat_bytes) + " bytes of compressed data can hold at most " +
               std::to_string(idat_bytes * kMaxDeflateRatio) + "; expected a complete PNG file");
  }
}

// Walks the PNG chunk list so that a truncated file is reported with the byte offset where it
// breaks off (libpng itself only says "Read Error"); then checks the image size against the
// compressed data (CheckPngDataSize).
void CheckPngChunks(const std::vector<uint8_t>& bytes, const std::string& name) {
  size_t offset = 8;
  long long idat_bytes = 0;
  while (true) {
    if (offset + 8 > bytes.size()) {
      FailAt(name, bytes.size(),
             "truncated PNG: the file ends inside a chunk header; expected a complete PNG file "
             "ending in an IEND chunk");
    }
    const uint32_t length = ReadBigEndian32(&bytes[offset]);
    const std::string type(reinterpret_cast<const char*>(&bytes[offset + 4]), 4);
    if (length > 0x7fffffffu) {
      FailAt(
          name, offset,
          "corrupt PNG: chunk length " + std::to_string(length) + "; expected at most 2147483647");
    }
    if (offset + 12 + length > bytes.size()) {
      FailAt(name, bytes.size(),
             "truncated PNG: chunk '" + type + "' at byte " + std::to_string(offset) + " needs " +
                 std::to_string(length + 12) + " bytes but the file ends after " +
                 std::to_string(bytes.size() - offset) + "; expected a complete PNG file");
    }
    if (type == "IDAT") idat_bytes += length;
    if (type == "IEND") {
      CheckPngDataSize(bytes, name, idat_bytes);
      return;
    }
    offset += 12 + length;
  }
}

// Every 8x8 block costs at least a DC and an end-of-block Huffman code (>= 2 bits), so even a
// flat grey JPEG needs a byte per 256 pixels; 2048 leaves a factor 8. A small file claiming a huge
// size is rejected before the pixel buffer is allocated.
constexpr long long kMaxJpegPixelsPerByte = 2048;

struct JpegErrorManager {
  jpeg_error_mgr pub;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void JpegErrorExit(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

// Warnings (premature end of data, corrupt entropy data) are errors for us: the decoder would
// otherwise fill the missing part with grey and we would detect on invented pixels.
void JpegEmitMessage(j_common_ptr cinfo, int level) {
  if (level < 0) JpegErrorExit(cinfo);
}

// Plain C-style decoder: no C++ object with a destructor lives in this frame across setjmp.
// Returns false with `message` and `offset` filled on error.
bool DecodeJpegRaw(const uint8_t* data, size_t size, camera::Image* out, char* message,
                   size_t* offset) {
  jpeg_decompress_struct cinfo;
  JpegErrorManager err;
  cinfo.err = jpeg_std_error(&err.pub);
  err.pub.error_exit = JpegErrorExit;
  err.pub.emit_message = JpegEmitMessage;
  err.message[0] = '\0';
  if (setjmp(err.jump)) {
    std::snprintf(message, JMSG_LENGTH_MAX, "%s", err.message);
    // Running out of data is found at the end; otherwise the source position is where the
    // decoder had read to (the entropy decoder may have buffered a few bytes beyond the fault).
    if (err.pub.msg_code == JWRN_JPEG_EOF) {
      *offset = size;
    } else {
      *offset = cinfo.src != nullptr ? size - cinfo.src->bytes_in_buffer : 0;
    }
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  cinfo.out_color_space = JCS_RGB;
  const long long pixels = static_cast<long long>(cinfo.image_width) * cinfo.image_height;
  if (pixels > kMaxPixels) {
    std::snprintf(message, JMSG_LENGTH_MAX, "image size %ux%u is too large", cinfo.image_width,
                  cinfo.image_height);
    *offset = 0;
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  if (pixels > static_cast<long long>(size) * kMaxJpegPixelsPerByte) {
    std::snprintf(message, JMSG_LENGTH_MAX,
                  "image size %ux%u cannot be coded in %zu bytes, at most %lld pixels a byte",
                  cinfo.image_width, cinfo.image_height, size, kMaxJpegPixelsPerByte);
    *offset = 0;
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_start_decompress(&cinfo);
  out->width_px = static_cast<int>(cinfo.output_width);
  out->height_px = static_cast<int>(cinfo.output_height);
  out->format = camera::PixelFormat::kRgb8;
  out->data.resize(static_cast<size_t>(out->width_px) * out->height_px * 3);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row =
        out->data.data() + static_cast<size_t>(cinfo.output_scanline) * out->width_px * 3;
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return true;
}

// PPM header token reader with byte offsets for messages.
class PpmHeader {
 public:
  PpmHeader(const std::vector<uint8_t>& bytes, const std::string& name)
      : bytes_(bytes), name_(name) {}

  long long Number(const char* what) {
    SkipSpaceAndComments();
    const size_t start = pos_;
    last_start_ = start;
    long long value = 0;
    while (pos_ < bytes_.size() && bytes_[pos_] >= '0' && bytes_[pos_] <= '9') {
      value = value * 10 + (bytes_[pos_] - '0');
      if (value > 1'000'000'000)
        FailAt(name_, start,
               std::string("PPM ") + what + " too large; expected at most 1000000000");
      ++pos_;
    }
    if (pos_ == start) {
      FailAt(name_, start,
             std::string("bad PPM header: ") +
                 (pos_ >= bytes_.size() ? "the file ends" : "unexpected character") +
                 "; expected the " + what + " (a decimal number)");
    }
    return value;
  }
  size_t pos() const { return pos_; }
  size_t last_start() const { return last_start_; }
  void Skip(size_t n) { pos_ += n; }

 private:
  void SkipSpaceAndComments() {
    while (pos_ < bytes_.size()) {
      const uint8_t c = bytes_[pos_];
      if (c == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        ++pos_;
      } else {
        break;
      }
    }
  }
  const std::vector<uint8_t>& bytes_;
  const std::string& name_;
  size_t pos_ = 0;
  size_t last_start_ = 0;
};

// The largest frame file: kMaxPixels of RGB plus room for headers and metadata.
constexpr size_t kMaxFrameFileBytes = static_cast<size_t>(kMaxPixels) * 3 + (1 << 20);
constexpr size_t kPpmHeaderBytes = 1 << 16;

// At most `n` first bytes of a file (fewer if it is shorter; none if it cannot be read: the
// full read reports that).
std::vector<uint8_t> ReadFileHead(const std::string& path, size_t n) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return {};
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> head(n);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(n));
  head.resize(in ? n : static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

// The width, height and maxval of a P6 header (the magic number already checked); the size
// checked against kMaxPixels.
void CheckPpmHeader(const std::vector<uint8_t>& head, const std::string& name) {
  PpmHeader header(head, name);
  header.Skip(2);
  const long long width = header.Number("width");
  const long long height = header.Number("height");
  CheckSize(name, width, height);
}

}  // namespace

namespace internal {

bool HasExtension(const fs::path& path, std::initializer_list<const char*> extensions) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* e : extensions) {
    if (ext == e) return true;
  }
  return false;
}

}  // namespace internal

using internal::HasExtension;

namespace {
std::vector<uint8_t> ReadFileBytesAtMost(const std::string& path, size_t max_bytes) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a directory; expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file; expected a readable file");
  const uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > max_bytes) {
    throw InputError(path + ": " + std::to_string(size) + " bytes; expected at most " +
                     std::to_string(max_bytes) + " bytes for a frame");
  }
  std::vector<uint8_t> bytes(ec ? 0 : static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}
}  // namespace

std::vector<uint8_t> ReadFileBytes(const std::string& path) {
  return ReadFileBytesAtMost(path, kMaxFrameFileBytes);
}

camera::Image DecodePng(const std::vector<uint8_t>& bytes, const std::string& name) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) {
    FailAt(name, 0, "not a PNG file; expected the 8-byte PNG signature");
  }
  CheckPngChunks(bytes, name);
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(name + ": corrupt PNG (libpng: " + message + "); expected a valid PNG image");
  }
  if (static_cast<long long>(png.width) * png.height > kMaxPixels) {
    png_image_free(&png);  // the size check must not leak libpng's read struct
    CheckSize(name, png.width, png.height);
  }
  png.format = PNG_FORMAT_RGB;
  camera::Image image;
  image.width_px = static_cast<int>(png.width);
  image.height_px = static_cast<int>(png.height);
  image.format = camera::PixelFormat::kRgb8;
  image.data.resize(PNG_IMAGE_SIZE(png));
  png_color black{0, 0, 0};
  if (!png_image_finish_read(&png, &black, image.data.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(name + ": corrupt PNG (libpng: " + message + "); expected a valid PNG image");
  }
  return image;
}

camera::Image DecodeJpeg(const std::vector<uint8_t>& bytes, const std::string& name) {
  camera::Image image;
  char message[JMSG_LENGTH_MAX] = {0};
  size_t offset = 0;
  if (!DecodeJpegRaw(bytes.data(), bytes.size(), &image, message, &offset)) {
    FailAt(name, offset,
           std::string("corrupt or truncated JPEG (libjpeg: ") + message +
               "); expected a complete JPEG image");
  }
  return image;
}

camera::Image DecodePpm(const std::vector<uint8_t>& bytes, const std::string& name) {
  if (bytes.size() < 2 || bytes[0] != 'P' || bytes[1] != '6') {
    FailAt(name, 0, "not a binary PPM; expected the magic number P6");
  }
  PpmHeader header(bytes, name);
  header.Skip(2);
  const long long width = header.Number("width");
  const long long height = header.Number("height");
  const long long maxval = header.Number("maxval");
  const size_t maxval_at = header.last_start();
  if (maxval != 255) {
    FailAt(name, maxval_at,
           "PPM maxval " + std::to_string(maxval) + "; expected 255 (8 bits per sample)");
  }
  CheckSize(name, width, height);
  const size_t data_at = header.pos() + 1;  // exactly one whitespace byte after maxval
  const size_t needed = static_cast<size_t>(width * height * 3);
  if (bytes.size() < data_at + needed) {
    FailAt(name, bytes.size(),
           "truncated PPM: " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
               std::to_string(needed) + " bytes of pixels from byte " + std::to_string(data_at) +
               "; expected a file of " + std::to_string(data_at + needed) + " bytes");
  }
  camera::Image image;
  image.width_px = static_cast<int>(width);
  image.height_px = static_cast<int>(height);
  image.format = camera::PixelFormat::kRgb8;
  image.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(data_at),
                    bytes.begin() + static_cast<std::ptrdiff_t>(data_at + needed));
  return image;
}

camera::Image ReadFrame(const std::string& path) {
  // A PPM header states the size: check it on the first bytes before reading a file of
  // gigabytes (a 20000x20000 PPM is rejected after 64 kB, not 1.2 GB).
  if (const std::vector<uint8_t> head = ReadFileHead(path, kPpmHeaderBytes);
      head.size() >= 2 && head[0] == 'P' && head[1] == '6') {
    CheckPpmHeader(head, path);
  }
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  if (bytes.size() >= 8 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[2] == 'N' &&
      bytes[3] == 'G') {
    return DecodePng(bytes, path);
  }
  if (bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) {
    return DecodeJpeg(bytes, path);
  }
  if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '6') return DecodePpm(bytes, path);
  if (IsRawFrameFile(path)) {
    throw InputError(path + ": a raw YUV frame has no header; expected --raw-size WIDTHxHEIGHT");
  }
  FailAt(path, 0, "unknown image format; expected a PNG, JPEG or binary PPM (P6) file");
}

bool IsRawFrameFile(const std::string& path) {
  return HasExtension(path, {".yuv", ".uyvy", ".raw"});
}

camera::Image ReadFrameFile(const std::string& path, int raw_width_px, int raw_height_px) {
  if (raw_width_px > 0 && IsRawFrameFile(path)) {
    return ReadRawUyvy(path, raw_width_px, raw_height_px);
  }
  return ReadFrame(path);
}

camera::Image ReadRawUyvy(const std::string& path, int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0 || width_px % 2 != 0) {
    throw InputError(path + ": raw frame size " + std::to_string(width_px) + "x" +
                     std::to_string(height_px) +
                     "; expected a positive even width and a positive height");
  }
  CheckSize(path, width_px, height_px);
  const size_t expected = static_cast<size_t>(width_px) * height_px * 2;
  // Read at most one byte more than a frame needs: a wrong size is found without reading a file
  // of gigabytes.
  std::vector<uint8_t> bytes;
  {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError(path + ": is a directory; expected a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file; expected a readable file");
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec && size != expected) {
      throw InputError(path + ": " + std::to_string(size) + " bytes; expected " +
                       std::to_string(expected) + " bytes for a " + std::to_string(width_px) + "x" +
                       std::to_string(height_px) + " UYVY frame (width x height x 2)");
    }
    bytes = ReadFileHead(path, expected + 1);
  }
  if (bytes.size() != expected) {
    throw InputError(path + ": " + std::to_string(bytes.size()) + " bytes; expected " +
                     std::to_string(expected) + " bytes for a " + std::to_string(width_px) + "x" +
                     std::to_string(height_px) + " UYVY frame (width x height x 2)");
  }
  camera::Image image;
  image.width_px = width_px;
  image.height_px = height_px;
  image.format = camera::PixelFormat::kUyvy;
  image.data = std::move(bytes);
  return image;
}

std::vector<uint8_t> EncodePng(const camera::Image& image) {
  const camera::Image rgb =
      image.format == camera::PixelFormat::kRgb8 ? camera::Image() : camera::ToRgb(image);
  const camera::Image& src = image.format == camera::PixelFormat::kRgb8 ? image : rgb;
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(src.width_px);
  png.height = static_cast<png_uint_32>(src.height_px);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  PATLAB_CHECK(png_image_write_get_memory_size(png, size, 0, src.data.data(), 0, nullptr));
  std::vector<uint8_t> out(size);
  PATLAB_CHECK(png_image_write_to_memory(&png, out.data(), &size, 0, src.data.data(), 0, nullptr));
  out.resize(size);
  return out;
}

namespace {
// One file through io::WriteFilesAtomic: a hidden temporary beside it, removed on any failure or
// on SIGINT/SIGTERM (docs/hardening.md).
void WriteAtomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  io::WriteFilesAtomic({{path, std::string(bytes.begin(), bytes.end())}});
}
}  // namespace

void WritePng(const camera::Image& image, const std::string& path) {
  WriteAtomically(path, EncodePng(image));
}

void WritePpm(const camera::Image& image, const std::string& path) {
  const camera::Image rgb = camera::ToRgb(image);
  const std::string header =
      "P6\n" + std::to_string(rgb.width_px) + " " + std::to_string(rgb.height_px) + "\n255\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), rgb.data.begin(), rgb.data.end());
  WriteAtomically(path, bytes);
}

}  // namespace patlab::vision

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

namespace patlab::vision {

namespace fs = std::filesystem;

namespace {

// Guards against a corrupt header asking for gigabytes.
constexpr long long kMaxPixels = 1LL << 28;

[[noreturn]] void FailAt(const std::string& name, size_t byte, const std::string& message) {
  throw InputError(name + ": byte " + std::to_string(byte) + ": " + message);
}

void CheckSize(const std::string& name, long long width, long long height) {
  if (width <= 0 || height <= 0 || width * height > kMaxPixels) {
    throw InputError(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     "; expected 1 to " + std::to_string(kMaxPixels) + " pixels");
  }
}

uint32_t ReadBigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

// Walks the PNG chunk list so that a truncated file is reported with the byte offset where it
// breaks off (libpng itself only says "Read Error").
void CheckPngChunks(const std::vector<uint8_t>& bytes, const std::string& name) {
  size_t offset = 8;
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
    if (type == "IEND") return;
    offset += 12 + length;
  }
}

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
bool DecodeJpegRaw(const uint8_t* data, size_t size, Image* out, char* message, size_t* offset) {
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
  if (static_cast<long long>(cinfo.image_width) * cinfo.image_height > kMaxPixels) {
    std::snprintf(message, JMSG_LENGTH_MAX, "image size %ux%u is too large", cinfo.image_width,
                  cinfo.image_height);
    *offset = 0;
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_start_decompress(&cinfo);
  out->width_px = static_cast<int>(cinfo.output_width);
  out->height_px = static_cast<int>(cinfo.output_height);
  out->format = PixelFormat::kRgb8;
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

bool HasExtension(const fs::path& path, std::initializer_list<const char*> extensions) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* e : extensions) {
    if (ext == e) return true;
  }
  return false;
}

}  // namespace

std::vector<uint8_t> ReadFileBytes(const std::string& path) {
  if (fs::is_directory(path)) throw InputError(path + ": is a directory; expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file; expected a readable file");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  return bytes;
}

Image DecodePng(const std::vector<uint8_t>& bytes, const std::string& name) {
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
  CheckSize(name, png.width, png.height);
  png.format = PNG_FORMAT_RGB;
  Image image;
  image.width_px = static_cast<int>(png.width);
  image.height_px = static_cast<int>(png.height);
  image.format = PixelFormat::kRgb8;
  image.data.resize(PNG_IMAGE_SIZE(png));
  png_color black{0, 0, 0};
  if (!png_image_finish_read(&png, &black, image.data.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(name + ": corrupt PNG (libpng: " + message + "); expected a valid PNG image");
  }
  return image;
}

Image DecodeJpeg(const std::vector<uint8_t>& bytes, const std::string& name) {
  Image image;
  char message[JMSG_LENGTH_MAX] = {0};
  size_t offset = 0;
  if (!DecodeJpegRaw(bytes.data(), bytes.size(), &image, message, &offset)) {
    FailAt(name, offset,
           std::string("corrupt or truncated JPEG (libjpeg: ") + message +
               "); expected a complete JPEG image");
  }
  return image;
}

Image DecodePpm(const std::vector<uint8_t>& bytes, const std::string& name) {
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
  Image image;
  image.width_px = static_cast<int>(width);
  image.height_px = static_cast<int>(height);
  image.format = PixelFormat::kRgb8;
  image.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(data_at),
                    bytes.begin() + static_cast<std::ptrdiff_t>(data_at + needed));
  return image;
}

Image ReadFrame(const std::string& path) {
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

Image ReadFrameFile(const std::string& path, int raw_width_px, int raw_height_px) {
  if (raw_width_px > 0 && IsRawFrameFile(path)) {
    return ReadRawUyvy(path, raw_width_px, raw_height_px);
  }
  return ReadFrame(path);
}

Image ReadRawUyvy(const std::string& path, int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0 || width_px % 2 != 0) {
    throw InputError(path + ": raw frame size " + std::to_string(width_px) + "x" +
                     std::to_string(height_px) +
                     "; expected a positive even width and a positive height");
  }
  CheckSize(path, width_px, height_px);
  std::vector<uint8_t> bytes = ReadFileBytes(path);
  const size_t expected = static_cast<size_t>(width_px) * height_px * 2;
  if (bytes.size() != expected) {
    throw InputError(path + ": " + std::to_string(bytes.size()) + " bytes; expected " +
                     std::to_string(expected) + " bytes for a " + std::to_string(width_px) + "x" +
                     std::to_string(height_px) + " UYVY frame (width x height x 2)");
  }
  Image image;
  image.width_px = width_px;
  image.height_px = height_px;
  image.format = PixelFormat::kUyvy;
  image.data = std::move(bytes);
  return image;
}

std::vector<uint8_t> EncodePng(const Image& image) {
  const Image rgb = image.format == PixelFormat::kRgb8 ? Image() : ToRgb(image);
  const Image& src = image.format == PixelFormat::kRgb8 ? image : rgb;
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
void WriteAtomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write file; expected a writable location");
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) throw InputError(path + ": cannot write file; expected a writable location");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot write file; expected a writable location");
  }
}
}  // namespace

void WritePng(const Image& image, const std::string& path) {
  WriteAtomically(path, EncodePng(image));
}

void WritePpm(const Image& image, const std::string& path) {
  const Image rgb = ToRgb(image);
  const std::string header =
      "P6\n" + std::to_string(rgb.width_px) + " " + std::to_string(rgb.height_px) + "\n255\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), rgb.data.begin(), rgb.data.end());
  WriteAtomically(path, bytes);
}

std::vector<std::string> ExpandFrameList(const std::vector<std::string>& arguments) {
  std::vector<std::string> frames;
  for (const std::string& argument : arguments) {
    const fs::path path(argument);
    if (!fs::exists(path))
      throw InputError(
          argument +
          ": no such file or directory; expected a frame, a directory of frames or a list file");
    if (fs::is_directory(path)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(path)) {
        if (entry.is_regular_file() && HasExtension(entry.path(), {".png", ".jpg", ".jpeg", ".ppm",
                                                                   ".yuv", ".uyvy", ".raw"})) {
          found.push_back(entry.path().string());
        }
      }
      if (found.empty()) {
        throw InputError(argument +
                         ": no frames in directory; expected files ending in .png, .jpg, .jpeg, "
                         ".ppm, .yuv, .uyvy or .raw");
      }
      std::sort(found.begin(), found.end());
      frames.insert(frames.end(), found.begin(), found.end());
    } else if (HasExtension(path, {".txt", ".list"})) {
      std::ifstream in(path);
      if (!in)
        throw InputError(argument + ": cannot open file; expected a readable list of frames");
      std::string line;
      while (std::getline(in, line)) {
        if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        const size_t begin = line.find_first_not_of(" \t\r");
        if (begin == std::string::npos) continue;
        const size_t end = line.find_last_not_of(" \t\r");
        fs::path frame(line.substr(begin, end - begin + 1));
        if (frame.is_relative()) frame = path.parent_path() / frame;
        frames.push_back(frame.string());
      }
    } else {
      frames.push_back(argument);
    }
  }
  return frames;
}

}  // namespace patlab::vision

// Stage 1 of the vision pipeline: reading frames. PNG (libpng), JPEG (libjpeg-turbo), binary
// PPM (P6), and raw YUV 4:2:2 (UYVY) of a given size, as cameras deliver them. Every problem
// with a file is an InputError "file: byte N: what is wrong; expected what" (or "file: ..."
// when no byte offset is known); nothing is returned for a bad file, so no partial frame leaks.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "patlab/camera/image.h"

namespace patlab::vision {

// The pixel budget of a frame: every reader checks width x height from the file's header against
// it before any pixel memory is allocated (2^28 pixels, 768 MiB as 8-bit RGB).
inline constexpr long long kMaxFramePixels = 1LL << 28;

// Reads a PNG, JPEG or PPM (P6, maxval 255) frame, chosen by the file's first bytes (not its
// name). Grey, palette, 16-bit and alpha PNGs are converted to 8-bit RGB.
camera::Image ReadFrame(const std::string& path);

// Reads a raw UYVY frame: exactly width_px * height_px * 2 bytes, width even.
camera::Image ReadRawUyvy(const std::string& path, int width_px, int height_px);

// True for the names of raw UYVY frames: .yuv .uyvy .raw (any case).
bool IsRawFrameFile(const std::string& path);
// A frame file as patlab detect reads it: a raw UYVY file of raw_width_px x raw_height_px when
// IsRawFrameFile(path) and a size is given (> 0), otherwise ReadFrame.
camera::Image ReadFrameFile(const std::string& path, int raw_width_px, int raw_height_px);

// The size a frame file states in its header, read from its first bytes without decoding any
// pixel: a PNG's IHDR, a JPEG's first SOF segment (within the first MiB), a binary PPM's width and
// height, and for a raw UYVY file (as ReadFrameFile reads it) raw_width_px x raw_height_px.
// std::nullopt when no size can be read there (not a frame, a damaged header): the decoder then
// says what is wrong. A stated size beyond the pixel budget is an InputError ("image size WxH;
// expected 1 to 268435456 pixels"). `patlab detect` checks it against the calibration's image
// size before it decodes the frame.
struct FrameHeaderSize {
  int width_px = 0;
  int height_px = 0;
};
std::optional<FrameHeaderSize> ReadFrameHeaderSize(const std::string& path, int raw_width_px,
                                                   int raw_height_px);

// Decoders from memory; `name` is used in messages.
camera::Image DecodePng(const std::vector<uint8_t>& bytes, const std::string& name);
camera::Image DecodeJpeg(const std::vector<uint8_t>& bytes, const std::string& name);
camera::Image DecodePpm(const std::vector<uint8_t>& bytes, const std::string& name);

// Writes an RGB frame as PNG atomically (temp file + rename). Throws InputError when the file
// cannot be written.
void WritePng(const camera::Image& image, const std::string& path);
// Encodes an RGB frame as PNG bytes.
std::vector<uint8_t> EncodePng(const camera::Image& image);
// Writes an RGB frame as binary PPM (P6).
void WritePpm(const camera::Image& image, const std::string& path);

// Expands the frame arguments of `patlab detect`, in order: a directory gives its frame files
// (.png .jpg .jpeg .ppm .yuv .uyvy .raw, sorted by name); a file ending in .txt or .list is a
// list of frame paths, one per line (relative to the list's directory, '#' starts a comment);
// anything else is a frame path. Throws InputError for a missing path or an empty directory.
std::vector<std::string> ExpandFrameList(const std::vector<std::string>& arguments);

// Reads a whole file; InputError when it cannot be opened, is a directory, or is larger than a
// frame can be (2^28 pixels of RGB plus 1 MiB), checked before anything is allocated.
std::vector<uint8_t> ReadFileBytes(const std::string& path);

}  // namespace patlab::vision

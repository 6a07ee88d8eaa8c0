// A decoded camera frame in memory, in the two layouts cameras and image files deliver: Image owns
// its packed pixels; ImageView reads pixels where they already are (a numpy array, a camera's
// buffer), with any strides, and is what the vision pipeline consumes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace patlab::camera {

enum class PixelFormat {
  kRgb8,  // 3 bytes per pixel, R G B, rows packed (PNG, JPEG, PPM after decoding)
  kUyvy,  // YUV 4:2:2, 2 bytes per pixel: U0 Y0 V0 Y1 per pixel pair (raw camera frames)
};

// Rows are packed (no padding): row y starts at data[y * RowBytes()].
// Pixel (i, j) is column i, row j; its centre is at (i, j) in pixel coordinates (OpenCV
// convention), so it covers [i - 0.5, i + 0.5) x [j - 0.5, j + 0.5).
struct Image {
  int width_px = 0;
  int height_px = 0;
  PixelFormat format = PixelFormat::kRgb8;
  std::vector<uint8_t> data;

  int BytesPerPixel() const { return format == PixelFormat::kRgb8 ? 3 : 2; }
  int RowBytes() const { return width_px * BytesPerPixel(); }
  const uint8_t* Row(int y) const { return data.data() + static_cast<std::size_t>(y) * RowBytes(); }
  uint8_t* Row(int y) { return data.data() + static_cast<std::size_t>(y) * RowBytes(); }

  static Image Rgb(int width_px, int height_px) {
    Image image;
    image.width_px = width_px;
    image.height_px = height_px;
    image.data.assign(static_cast<std::size_t>(width_px) * height_px * 3, 0);
    return image;
  }
};

// A frame's pixels in memory the view does not own (they must outlive its use), laid out with
// any strides in bytes, of any sign: channel c of pixel (i, j) is the byte at
//   data + j * row_stride + i * pixel_stride + c * channel_stride.
// An Image converts to the view of its packed rows (as std::string to std::string_view), so
// every function that takes a view takes an Image. RGB views may have any strides (a numpy
// (H, W, 3) array, its [:, :, ::-1] view of BGR bytes, the RGB channels of an RGBA buffer, a
// crop); UYVY views must have packed pixel pairs (pixel_stride 2, channel_stride 1) and any row
// stride.
struct ImageView {
  const uint8_t* data = nullptr;  // channel 0 of pixel (0, 0)
  int width_px = 0;
  int height_px = 0;
  PixelFormat format = PixelFormat::kRgb8;
  std::ptrdiff_t row_stride = 0;
  std::ptrdiff_t pixel_stride = 0;
  std::ptrdiff_t channel_stride = 1;

  ImageView() = default;
  ImageView(const Image& image)  // NOLINT(google-explicit-constructor): as string_view
      : data(image.data.data()),
        width_px(image.width_px),
        height_px(image.height_px),
        format(image.format),
        row_stride(image.RowBytes()),
        pixel_stride(image.BytesPerPixel()),
        channel_stride(1) {}

  int BytesPerPixel() const { return format == PixelFormat::kRgb8 ? 3 : 2; }
  // Pixels packed along each row (the rows themselves may be anywhere): row y is then
  // width_px * BytesPerPixel() consecutive bytes from Row(y), as in an Image.
  bool PackedPixels() const { return pixel_stride == BytesPerPixel() && channel_stride == 1; }
  const uint8_t* Row(int y) const { return data + static_cast<std::ptrdiff_t>(y) * row_stride; }
};

// ITU-R BT.601 full-range conversions, the ones CMVision's YUV thresholds and UYVY cameras use.
// Fixed point with 8 fraction bits; every output is clamped to 0..255.
inline void RgbToYuv(int r, int g, int b, int* y, int* u, int* v) {
  auto clamp = [](int x) { return x < 0 ? 0 : (x > 255 ? 255 : x); };
  *y = clamp((77 * r + 150 * g + 29 * b + 128) >> 8);
  *u = clamp(((-43 * r - 85 * g + 128 * b + 128) >> 8) + 128);
  *v = clamp(((128 * r - 107 * g - 21 * b + 128) >> 8) + 128);
}

inline void YuvToRgb(int y, int u, int v, int* r, int* g, int* b) {
  auto clamp = [](int x) { return x < 0 ? 0 : (x > 255 ? 255 : x); };
  const int d = u - 128, e = v - 128;
  *r = clamp(y + ((359 * e + 128) >> 8));
  *g = clamp(y - ((88 * d + 183 * e + 128) >> 8));
  *b = clamp(y + ((454 * d + 128) >> 8));
}

// Converts a frame to packed RGB (a copy when it already is).
Image ToRgb(const Image& image);
// The viewed frame as a packed RGB image of its own (a copy, converted from UYVY).
Image ToRgb(const ImageView& view);
// The same into `out`, whose buffer is reused: once it has held a frame of this size, converting
// the next allocates nothing.
void ToRgb(const ImageView& view, Image* out);
// Converts an RGB frame to UYVY (U and V averaged over each pixel pair); width must be even.
Image ToUyvy(const Image& image);

// The frame binned `factor` x `factor` (>= 1): pixel (i, j) of the packed RGB result is the mean,
// rounded, of the block of pixels [factor i, factor i + factor) x [factor j, factor j + factor)
// (UYVY converted to RGB first); the result is floor(width / factor) x floor(height / factor)
// and the frame's last rows and columns that fill no block are dropped. Its pixel (i, j) covers
// what the frame's (factor (i + 0.5) - 0.5, factor (j + 0.5) - 0.5) is the centre of: the
// calibration of camera.h's CameraModel::Resized(1 / factor). `out`'s buffer is reused.
void BinImage(const ImageView& view, int factor, Image* out);

}  // namespace patlab::camera

#include "patlab/camera/image.h"

#include <algorithm>
#include <vector>

#include "patlab/core/error.h"

namespace patlab::camera {

Image ToRgb(const Image& image) {
  if (image.format == PixelFormat::kRgb8) return image;
  return ToRgb(ImageView(image));
}

Image ToRgb(const ImageView& view) {
  Image rgb;
  ToRgb(view, &rgb);
  return rgb;
}

void ToRgb(const ImageView& view, Image* out) {
  out->width_px = view.width_px;
  out->height_px = view.height_px;
  out->format = PixelFormat::kRgb8;
  out->data.resize(static_cast<std::size_t>(view.width_px) * view.height_px * 3);
  for (int y = 0; y < view.height_px; ++y) {
    const uint8_t* in = view.Row(y);
    uint8_t* row = out->Row(y);
    if (view.format == PixelFormat::kRgb8) {
      for (int x = 0; x < view.width_px; ++x) {
        for (int c = 0; c < 3; ++c)
          row[3 * x + c] = in[x * view.pixel_stride + c * view.channel_stride];
      }
      continue;
    }
    // UYVY views have packed pixel pairs: U Y0 V Y1.
    for (int x = 0; x + 1 < view.width_px; x += 2, in += 4, row += 6) {
      for (int k = 0; k < 2; ++k) {
        int r, g, b;
        YuvToRgb(in[1 + 2 * k], in[0], in[2], &r, &g, &b);
        row[3 * k + 0] = static_cast<uint8_t>(r);
        row[3 * k + 1] = static_cast<uint8_t>(g);
        row[3 * k + 2] = static_cast<uint8_t>(b);
      }
    }
  }
}

Image ToUyvy(const Image& image) {
  if (image.format == PixelFormat::kUyvy) return image;
  PATLAB_CHECK(image.width_px % 2 == 0);
  Image yuv;
  yuv.width_px = image.width_px;
  yuv.height_px = image.height_px;
  yuv.format = PixelFormat::kUyvy;
  yuv.data.resize(static_cast<size_t>(image.width_px) * image.height_px * 2);
  for (int y = 0; y < image.height_px; ++y) {
    const uint8_t* in = image.Row(y);
    uint8_t* out = yuv.Row(y);
    for (int x = 0; x + 1 < image.width_px; x += 2, in += 6, out += 4) {
      int y0, u0, v0, y1, u1, v1;
      RgbToYuv(in[0], in[1], in[2], &y0, &u0, &v0);
      RgbToYuv(in[3], in[4], in[5], &y1, &u1, &v1);
      out[0] = static_cast<uint8_t>((u0 + u1 + 1) / 2);
      out[1] = static_cast<uint8_t>(y0);
      out[2] = static_cast<uint8_t>((v0 + v1 + 1) / 2);
      out[3] = static_cast<uint8_t>(y1);
    }
  }
  return yuv;
}

void BinImage(const ImageView& view, int factor, Image* out) {
  PATLAB_CHECK(factor >= 1);
  Image rgb;
  const bool packed_rgb = view.format == PixelFormat::kRgb8 && view.PackedPixels();
  if (!packed_rgb) ToRgb(view, &rgb);
  const ImageView in = packed_rgb ? view : ImageView(rgb);
  out->width_px = in.width_px / factor;
  out->height_px = in.height_px / factor;
  out->format = PixelFormat::kRgb8;
  out->data.assign(static_cast<std::size_t>(out->width_px) * out->height_px * 3, 0);
  const int area = factor * factor;
  std::vector<int> sums(static_cast<std::size_t>(out->width_px) * 3);
  for (int y = 0; y < out->height_px; ++y) {
    std::fill(sums.begin(), sums.end(), 0);
    for (int dy = 0; dy < factor; ++dy) {
      const uint8_t* row = in.Row(factor * y + dy);
      for (std::size_t i = 0; i < sums.size(); i += 3, row += 3 * factor) {
        for (int dx = 0; dx < 3 * factor; dx += 3) {
          for (std::size_t c = 0; c < 3; ++c) sums[i + c] += row[dx + c];
        }
      }
    }
    uint8_t* row = out->Row(y);
    for (std::size_t i = 0; i < sums.size(); ++i) {
      row[i] = static_cast<uint8_t>((sums[i] + area / 2) / area);
    }
  }
}

}  // namespace patlab::camera

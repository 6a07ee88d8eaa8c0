// The white field lines of a frame (field_lines.h).
#include "patlab/vision/field_lines.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "patlab/calib/field_marks.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/render/draw.h"

namespace patlab::vision {
namespace {

// A float image, row-major.
struct Plane {
  int w = 0, h = 0;
  std::vector<float> v;
  float& at(int x, int y) { return v[static_cast<size_t>(y) * w + x]; }
  float at(int x, int y) const { return v[static_cast<size_t>(y) * w + x]; }
};

Plane Blank(int w, int h) { return Plane{w, h, std::vector<float>(static_cast<size_t>(w) * h)}; }

// Separable Gaussian smoothing (edges clamped).
Plane Smooth(const Plane& in, double sigma) {
  const int r = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<float> k(2 * r + 1);
  double sum = 0.0;
  for (int i = -r; i <= r; ++i)
    sum += k[i + r] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (float& x : k) x = static_cast<float>(x / sum);
  Plane tmp = Blank(in.w, in.h), out = Blank(in.w, in.h);
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * in.at(std::clamp(x + i, 0, in.w - 1), y);
      tmp.at(x, y) = s;
    }
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * tmp.at(x, std::clamp(y + i, 0, in.h - 1));
      out.at(x, y) = s;
    }
  return out;
}

// The mean over a (2 r + 1)^2 window (clipped to the image), by an integral image.
Plane BoxMean(const Plane& in, int r) {
  std::vector<double> sat(static_cast<size_t>(in.w + 1) * (in.h + 1), 0.0);
  auto s = [&](int x, int y) -> double& { return sat[static_cast<size_t>(y) * (in.w + 1) + x]; };
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x)
      s(x + 1, y + 1) = in.at(x, y) + s(x, y + 1) + s(x + 1, y) - s(x, y);
  Plane out = Blank(in.w, in.h);
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(in.w, x + r + 1);
      const int y0 = std::max(0, y - r), y1 = std::min(in.h, y + r + 1);
      out.at(x, y) = static_cast<float>((s(x1, y1) - s(x0, y1) - s(x1, y0) + s(x0, y0)) /
                                        ((x1 - x0) * (y1 - y0)));
    }
  return out;
}

void Check(const LineFinderOptions& o) {
  if (!(o.line_width_px >= 1.0 && o.line_width_px <= 30.0))
    throw InputError("--line-width: " + FormatNumber(o.line_width_px) +
                     " px is out of range; expected 1 to 30");
  if (!(o.min_contrast > 0.0 && o.min_contrast <= 255.0))
    throw InputError("line finder: min_contrast must be in (0, 255]");
  if (!(o.max_chroma > 0.0 && o.max_chroma <= 255.0))
    throw InputError("line finder: max_chroma must be in (0, 255]");
  if (o.background_window_px < 5 || o.background_window_px > 255 || o.background_window_px % 2 == 0)
    throw InputError("line finder: background_window_px must be odd, in [5, 255]");
}

}  // namespace

std::vector<calib::LinePixel> FindLinePixels(const camera::Image& frame,
                                             const LineFinderOptions& options) {
  Check(options);
  const camera::Image rgb = camera::ToRgb(frame);
  const int w = rgb.width_px, h = rgb.height_px;
  std::vector<calib::LinePixel> out;
  if (w < 8 || h < 8) return out;
  Plane luma = Blank(w, h), chroma = Blank(w, h);
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = rgb.Row(y);
    for (int x = 0; x < w; ++x) {
      int yy, u, v;
      camera::RgbToYuv(row[3 * x], row[3 * x + 1], row[3 * x + 2], &yy, &u, &v);
      luma.at(x, y) = static_cast<float>(yy);
      chroma.at(x, y) = static_cast<float>(std::abs(u - 128) + std::abs(v - 128));
    }
  }
  // Steger's scale for a bar of width w: sigma = w / (2 sqrt 3).
  const double sigma = std::max(0.7, options.line_width_px / (2.0 * std::sqrt(3.0)));
  const Plane g = Smooth(luma, sigma);
  const Plane c = Smooth(chroma, sigma);
  const Plane carpet = BoxMean(luma, options.background_window_px / 2);
  // A bar of contrast C at this scale has a second derivative of about -0.31 C / sigma^2 at its
  // centre; half of that for the weakest line kept.
  const double min_curvature = 0.15 * options.min_contrast / (sigma * sigma);
  const int border = 2;
  for (int y = border; y < h - border; ++y) {
    for (int x = border; x < w - border; ++x) {
      const double lift = g.at(x, y) - carpet.at(x, y);
      if (lift < 0.5 * options.min_contrast || c.at(x, y) > options.max_chroma) continue;
      const double gxx = g.at(x + 1, y) - 2.0 * g.at(x, y) + g.at(x - 1, y);
      const double gyy = g.at(x, y + 1) - 2.0 * g.at(x, y) + g.at(x, y - 1);
      const double gxy = 0.25 * (g.at(x + 1, y + 1) - g.at(x - 1, y + 1) - g.at(x + 1, y - 1) +
                                 g.at(x - 1, y - 1));
      // The eigenvalues of [[gxx, gxy], [gxy, gyy]]; lambda the most negative.
      const double mean = 0.5 * (gxx + gyy), diff = std::hypot(0.5 * (gxx - gyy), gxy);
      const double lambda = mean - diff, other = mean + diff;
      if (-lambda < min_curvature || std::abs(other) > 0.5 * std::abs(lambda)) continue;
      Vec2 n =
          std::abs(gxy) > 1e-12 ? Vec2(gxy, lambda - gxx) : (gxx < gyy ? Vec2(1, 0) : Vec2(0, 1));
      n.normalize();
      const double gx = 0.5 * (g.at(x + 1, y) - g.at(x - 1, y));
      const double gy = 0.5 * (g.at(x, y + 1) - g.at(x, y - 1));
      const double t = -(gx * n.x() + gy * n.y()) / lambda;
      if (std::abs(t * n.x()) > 0.5 || std::abs(t * n.y()) > 0.5) continue;
      calib::LinePixel p;
      p.pixel = Vec2(x + t * n.x(), y + t * n.y());
      p.direction = Vec2(-n.y(), n.x());
      p.strength = -lambda * sigma * sigma;
      out.push_back(p);
    }
  }
  return out;
}

camera::Image DrawLinePixels(const camera::Image& frame,
                             const std::vector<calib::LinePixel>& pixels, const calib::Field* field,
                             const calib::AutoCalibration* fit) {
  camera::Image out = camera::ToRgb(frame);
  for (uint8_t& v : out.data) v = static_cast<uint8_t>(v / 2);
  if (field != nullptr && fit != nullptr) {
    const camera::CameraModel cam = camera::CameraModel::Pinhole(fit->fit.camera);
    const calib::FieldMarks marks = calib::PaintedMarks(*field);
    std::vector<int> mark;
    for (const Vec2& q : calib::SampleMarks(marks, 5.0, &mark)) {
      const auto px = cam.WorldToPixel(q, 0.0);
      if (px)
        render::PutPixel(&out, static_cast<int>(std::lround(px->x())),
                         static_cast<int>(std::lround(px->y())), {0, 255, 255});
    }
  }
  for (const calib::LinePixel& p : pixels)
    render::PutPixel(&out, static_cast<int>(std::lround(p.pixel.x())),
                     static_cast<int>(std::lround(p.pixel.y())), {255, 40, 40});
  return out;
}

FrameCalibration AutoCalibrateFrame(const camera::Image& frame, const std::string& source,
                                    const calib::Field& field, const LineFinderOptions& finder,
                                    const calib::AutoOptions& options) {
  FrameCalibration out;
  const auto t0 = std::chrono::steady_clock::now();
  out.pixels = FindLinePixels(frame, finder);
  out.find_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.calibration =
      calib::AutoCalibrate(out.pixels, frame.width_px, frame.height_px, source, field, options);
  return out;
}

}  // namespace patlab::vision

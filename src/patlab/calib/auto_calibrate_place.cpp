// Crossing field lines placed on the line pixels through a camera of known floor scale
// (auto_calibrate.h PlaceCrossings): where the lines alone match too few marks to fix a camera.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "patlab/calib/auto_calibrate_internal.h"
#include "patlab/core/error.h"

namespace patlab::calib {
namespace {

constexpr double kMaxSin = 0.42;   // |sin| between a pixel's direction and an axis, on the floor
constexpr double kBinMm = 20.0;    // the histograms' bin across the lines
constexpr int kMinLinePixels = 8;  // a histogram peak's run of pixels at least
constexpr double kGapPx = 3.0;     // the most between neighbours of a run along a line
constexpr int kPeaksPerAxis = 2;   // the strongest lines along each axis tried

// A line pixel on the floor through the floor camera: its point and unit direction.
struct FloorPixel {
  Vec2 at = Vec2::Zero();
  Vec2 direction = Vec2(1, 0);
};

std::vector<FloorPixel> OnTheFloor(const std::vector<LinePixel>& pixels,
                                   const camera::PinholeCamera& camera) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  std::vector<FloorPixel> out;
  for (const LinePixel& p : pixels) {
    const auto q = model.PixelToWorld(p.pixel, 0.0);
    const auto q2 = model.PixelToWorld(p.pixel + 2.0 * p.direction, 0.0);
    if (!q || !q2 || (*q2 - *q).norm() <= 0.0) continue;
    out.push_back({*q, (*q2 - *q).normalized()});
  }
  return out;
}

// The dominant direction modulo 90 deg (rad): the mean of the directions' angles times four.
double DominantAngle(const std::vector<FloorPixel>& pixels) {
  std::complex<double> sum = 0.0;
  for (const FloorPixel& p : pixels)
    sum += std::polar(1.0, 4.0 * std::atan2(p.direction.y(), p.direction.x()));
  return 0.25 * std::arg(sum);
}

// The longest run of `along` (sorted) with no gap over gap_mm between neighbours: [first, last).
std::pair<size_t, size_t> LongestRun(const std::vector<double>& along, double gap_mm) {
  std::pair<size_t, size_t> best{0, 0};
  size_t first = 0;
  for (size_t i = 1; i <= along.size(); ++i) {
    if (i < along.size() && along[i] - along[i - 1] <= gap_mm) continue;
    if (i - first > best.second - best.first) best = {first, i};
    first = i;
  }
  return best;
}

// The strongest lines across one axis (the coordinate `across` of the pixels running along the
// other), each the mean coordinate of a histogram peak's pixels, where they hold a run along the
// line of kMinLinePixels (neighbours at most gap_mm apart): a line is a run, not pixels strewn
// along a band of the floor
// (fresh rendered seed 115: one touch line in view, and 11-19 pixels strewn over up to 2 m in a
// band across it made a second "line" and a crossing that placed the robots 2.5 m off).
std::vector<double> Peaks(const std::vector<Vec2>& turned, const std::vector<Vec2>& directions,
                          int along_axis, double gap_mm) {
  const int across = 1 - along_axis;
  std::vector<Vec2> values;  // (across, along)
  for (size_t i = 0; i < turned.size(); ++i)
    if (std::abs(directions[i][across]) < kMaxSin)
      values.emplace_back(turned[i][across], turned[i][along_axis]);
  if (values.empty()) return {};
  const auto range = std::minmax_element(
      values.begin(), values.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
  const double lo = range.first->x(), hi = range.second->x();
  const int bins = static_cast<int>((hi - lo) / kBinMm) + 1;
  std::vector<int> count(static_cast<size_t>(bins), 0);
  const auto bin = [lo](double v) { return static_cast<int>((v - lo) / kBinMm); };
  for (const Vec2& v : values) ++count[static_cast<size_t>(bin(v.x()))];
  const auto near = [&](int b) {
    return count[static_cast<size_t>(b)] + (b > 0 ? count[static_cast<size_t>(b - 1)] : 0) +
           (b + 1 < bins ? count[static_cast<size_t>(b + 1)] : 0);
  };
  std::vector<double> peaks;
  std::vector<bool> used(count.size(), false);
  while (static_cast<int>(peaks.size()) < kPeaksPerAxis) {
    int best = -1;
    for (int b = 0; b < bins; ++b) {
      if (!used[static_cast<size_t>(b)] && near(b) >= kMinLinePixels &&
          (best < 0 || near(b) > near(best)))
        best = b;
    }
    if (best < 0) break;
    std::vector<Vec2> band;
    for (const Vec2& v : values)
      if (std::abs(bin(v.x()) - best) <= 1) band.push_back(v);
    std::sort(band.begin(), band.end(), [](const Vec2& a, const Vec2& b) { return a.y() < b.y(); });
    std::vector<double> along;
    for (const Vec2& v : band) along.push_back(v.y());
    const auto [first, last] = LongestRun(along, gap_mm);
    if (last - first >= static_cast<size_t>(kMinLinePixels)) {
      double sum = 0.0;
      for (const Vec2& v : values)  // the band's pixels in their histogram order
        if (std::abs(bin(v.x()) - best) <= 1) sum += v.x();
      peaks.push_back(sum / static_cast<double>(band.size()));
      for (int b = std::max(0, best - 3); b <= std::min(bins - 1, best + 3); ++b)
        used[static_cast<size_t>(b)] = true;
    } else {
      used[static_cast<size_t>(best)] = true;  // strewn pixels: no line here
    }
  }
  return peaks;
}

// The crossing of two painted lines of a model, one along x and one along y, within both.
struct Crossing {
  std::string name;
  Vec2 at = Vec2::Zero();
};
std::vector<Crossing> Crossings(const Field& field) {
  std::vector<Crossing> out;
  constexpr double kTouch = 1.0;  // mm
  for (const FieldLine& a : field.lines) {
    if (!IsPaintedLine(a) || std::abs(a.from_mm.y() - a.to_mm.y()) > kTouch) continue;
    for (const FieldLine& b : field.lines) {
      if (!IsPaintedLine(b) || std::abs(b.from_mm.x() - b.to_mm.x()) > kTouch) continue;
      const Vec2 at(b.from_mm.x(), a.from_mm.y());
      const auto within = [&](double v, double p, double q) {
        return v >= std::min(p, q) - kTouch && v <= std::max(p, q) + kTouch;
      };
      if (within(at.x(), a.from_mm.x(), a.to_mm.x()) && within(at.y(), b.from_mm.y(), b.to_mm.y()))
        out.push_back({a.name + " x " + b.name, at});
    }
  }
  return out;
}

Eigen::Matrix2d Rotation(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

// `camera` with its floor moved: a floor point p of the camera's map is q = Rot(turn) p + shift.
camera::PinholeCamera Moved(const camera::PinholeCamera& camera, double turn, const Vec2& shift) {
  Eigen::Matrix3d q = Eigen::Matrix3d::Identity();
  q.topLeftCorner<2, 2>() = Rotation(turn);
  camera::PinholeCamera out = camera;
  out.rotation = camera.rotation * q.transpose();
  out.translation_mm =
      camera.translation_mm - out.rotation * Eigen::Vector3d(shift.x(), shift.y(), 0.0);
  return out;
}

}  // namespace

std::vector<Placement> PlaceCrossings(const std::vector<LinePixel>& pixels, int width_px,
                                      int height_px, const std::string& source,
                                      const std::vector<Field>& fields,
                                      const camera::PinholeCamera& floor_camera, double gate_px,
                                      const AutoOptions& options) {
  const std::vector<FloorPixel> floor = OnTheFloor(pixels, floor_camera);
  if (floor.empty()) return {};
  // The pixels turned so that their lines run along the axes.
  const double psi = DominantAngle(floor);
  const Eigen::Matrix2d unturn = Rotation(-psi);
  std::vector<Vec2> turned, directions;
  for (const FloorPixel& p : floor) {
    turned.push_back(unturn * p.at);
    directions.push_back(unturn * p.direction);
  }
  // Neighbours along a line are about a pixel apart: gaps up to kGapPx at the image centre's
  // floor scale (a robot across a line breaks it into two runs).
  const camera::CameraModel floor_model = camera::CameraModel::Pinhole(floor_camera);
  const double mm_per_px = std::sqrt(std::max(
      1e-9, floor_model.AreaScale(Vec2(0.5 * (width_px - 1), 0.5 * (height_px - 1)), 0.0)));
  const double gap_mm = kGapPx * mm_per_px;
  const std::vector<double> across_y = Peaks(turned, directions, 0, gap_mm);  // along x: their y
  const std::vector<double> across_x = Peaks(turned, directions, 1, gap_mm);  // along y: their x
  const CalibrationInput base = internal::BaseInput(source, width_px, height_px, options);
  const internal::LineDistance distance(pixels, width_px, height_px);
  std::vector<Placement> out;
  for (size_t m = 0; m < fields.size(); ++m) {
    const FieldMarks field_marks = PaintedMarks(fields[m]);
    MarkSampler marks(field_marks);
    for (const Crossing& c : Crossings(fields[m])) {
      for (double y : across_y) {
        for (double x : across_x) {
          // The observed crossing (on the camera's floor) onto the model's, in each quarter turn.
          const Vec2 seen = unturn.transpose() * Vec2(x, y);
          for (int k = 0; k < 4; ++k) {
            const double turn = -psi + 0.5 * std::numbers::pi * k;
            const Vec2 shift = c.at - Rotation(turn) * seen;
            Placement p;
            p.model = static_cast<int>(m);
            p.crossing = c.name;
            p.camera = Moved(floor_camera, turn, shift);
            p.score_px = internal::CameraScore(p.camera, marks, distance);
            out.push_back(std::move(p));
          }
        }
      }
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Placement& a, const Placement& b) { return a.score_px > b.score_px; });
  // Placements explaining less than half the best's line are not worth their assignment.
  if (!out.empty()) {
    const double least = 0.5 * out.front().score_px;
    std::erase_if(out, [&](const Placement& p) { return !(p.score_px >= least); });
  }
  for (Placement& p : out) {
    p.input = AssignToMarks(p.camera, pixels, fields[static_cast<size_t>(p.model)], gate_px,
                            options.max_fit_pixels, base);
  }
  return out;
}

}  // namespace patlab::calib

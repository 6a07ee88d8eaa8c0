// The automatic field calibration's search for the camera (auto_calibrate.h steps 1-3).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/calib/auto_calibrate_internal.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::calib::internal {
namespace {

constexpr double kTauPx = 6.0;          // a mark within this of a line pixel is explained
constexpr double kCoarseTauPx = 16.0;   // the same for the unrefined hypotheses
constexpr double kPenalty = 0.5;        // per unexplained length, of an explained one
constexpr double kAxisTolerance = 0.2;  // |sin| of a pixel's angle to an image axis
constexpr double kBinPx = 3.0;

// The view's map with cos and sin of its psi given (computed once per view, not per point).
Vec2 Apply(const NadirView& v, const Vec2& p, double width, double c, double s) {
  const Vec2 d = p - v.centre_mm;
  Vec2 ab;
  switch (v.k & 3) {
    case 0:
      ab = Vec2(d.x(), -d.y());
      break;
    case 1:
      ab = Vec2(d.y(), d.x());
      break;
    case 2:
      ab = Vec2(-d.x(), d.y());
      break;
    default:
      ab = Vec2(-d.y(), -d.x());
      break;
  }
  ab *= v.scale;
  const Vec2 q(c * ab.x() - s * ab.y(), s * ab.x() + c * ab.y());
  return q * (1.0 + v.kd * q.squaredNorm() / (width * width));
}

// The score of points `world` through `project` (px of line length).
template <typename Project>
double Score(const std::vector<Vec2>& world, double spacing_px, const LineDistance& dt,
             Project project, double tau = kTauPx) {
  double sum = 0.0;
  for (const Vec2& p : world) {
    const auto q = project(p);
    if (!q || q->x() < 0 || q->y() < 0 || q->x() > dt.width() - 1 || q->y() > dt.height() - 1)
      continue;
    const double d = dt.At(*q);
    sum += d <= tau ? 1.0 - (d * d) / (tau * tau) : -kPenalty;
  }
  return sum * spacing_px;
}

// The coarse score (tau kCoarseTauPx) of image points `base` shifted by `shift`: Score's sum
// with the projection done once for every view of one scale and orientation.
double ShiftedScore(const std::vector<Vec2>& base, const Vec2& shift, double spacing_px,
                    const LineDistance& dt) {
  const double w = dt.width() - 1, h = dt.height() - 1;
  constexpr double kTau2 = kCoarseTauPx * kCoarseTauPx;
  double sum = 0.0;
  for (const Vec2& b : base) {
    const Vec2 q = b + shift;
    if (q.x() < 0 || q.y() < 0 || q.x() > w || q.y() > h) continue;
    const double d = dt.At(q);
    sum += d <= kCoarseTauPx ? 1.0 - (d * d) / kTau2 : -kPenalty;
  }
  return sum * spacing_px;
}

// The score of a view of the marks sampled at step_px / v.scale mm (`world`).
double ViewScoreOf(const NadirView& v, const std::vector<Vec2>& world, const LineDistance& dt,
                   double step_px, double tau) {
  const Vec2 c(0.5 * (dt.width() - 1), 0.5 * (dt.height() - 1));
  const double cp = std::cos(v.psi), sp = std::sin(v.psi);
  return Score(
      world, step_px, dt,
      [&](const Vec2& p) -> std::optional<Vec2> { return c + Apply(v, p, dt.width(), cp, sp); },
      tau);
}

double ViewScore(const NadirView& v, MarkSampler& marks, const LineDistance& dt, double step_px,
                 double tau = kTauPx) {
  return ViewScoreOf(v, marks.Sample(step_px / v.scale), dt, step_px, tau);
}

// Peaks of a histogram of positions across one image axis: (position px, weight).
std::vector<double> Peaks(const std::vector<double>& positions, double extent) {
  const int bins = static_cast<int>(2 * extent / kBinPx) + 1;
  std::vector<double> h(static_cast<size_t>(bins), 0.0), sm(h.size(), 0.0);
  for (double p : positions) {
    const int b = static_cast<int>((p + extent) / kBinPx);
    if (b >= 0 && b < bins) h[static_cast<size_t>(b)] += 1.0;
  }
  for (int b = 0; b < bins; ++b)
    for (int j = -2; j <= 2; ++j)
      if (b + j >= 0 && b + j < bins) sm[b] += h[b + j] * (3 - std::abs(j));
  const double top = *std::max_element(sm.begin(), sm.end());
  std::vector<std::pair<double, double>> peaks;
  for (int b = 0; b < bins; ++b) {
    bool is_max = sm[b] >= std::max(20.0, 0.08 * top);
    for (int j = -4; j <= 4 && is_max; ++j)
      if (j != 0 && b + j >= 0 && b + j < bins && sm[b + j] > sm[b]) is_max = false;
    if (is_max && (peaks.empty() || (b + 0.5) * kBinPx - extent - peaks.back().second > 4 * kBinPx))
      peaks.emplace_back(sm[b], (b + 0.5) * kBinPx - extent);
  }
  std::sort(peaks.begin(), peaks.end(), std::greater<>());
  if (peaks.size() > 8) peaks.resize(8);
  std::vector<double> out;
  for (const auto& p : peaks) out.push_back(p.second);
  return out;
}

void Refine(ScoredView& sv, MarkSampler& marks, const LineDistance& dt, double tau) {
  double steps[5] = {0.02, 0.01, 4.0 / sv.view.scale, 4.0 / sv.view.scale, 0.04};
  auto with = [&](int i, double d) {
    NadirView v = sv.view;
    if (i == 0) v.scale *= std::exp(d);
    if (i == 1) v.psi += d;
    if (i == 2) v.centre_mm.x() += d;
    if (i == 3) v.centre_mm.y() += d;
    if (i == 4) v.kd = std::clamp(v.kd + d, -0.6, 0.3);
    return v;
  };
  for (int round = 0; round < 6; ++round) {
    bool improved = true;
    for (int pass = 0; pass < 8 && improved; ++pass) {
      improved = false;
      for (int i = 0; i < 5; ++i) {
        for (double sign : {1.0, -1.0}) {
          const NadirView v = with(i, sign * steps[i]);
          const double score = ViewScore(v, marks, dt, 4.0, tau);
          if (score > sv.score) sv.view = v, sv.score = score, improved = true;
        }
      }
    }
    for (double& s : steps) s *= 0.5;
  }
}

// The camera refined by coordinate descent on the score: rotation about its own axes, centre,
// height and k1 (the focal length stays: the floor alone hardly separates it from the height).
void RefineCamera(ScoredView& sv, MarkSampler& marks, const LineDistance& dt, double tau) {
  const double height = (-sv.camera.rotation.transpose() * sv.camera.translation_mm).z();
  const double mm_per_px = height / sv.camera.fx_px;
  double steps[7] = {0.02, 0.02, 0.02, 6 * mm_per_px, 6 * mm_per_px, 0.03, 0.04};
  auto with = [&](int i, double d) {
    camera::PinholeCamera c = sv.camera;
    Eigen::Vector3d centre = -c.rotation.transpose() * c.translation_mm;
    if (i < 3) {
      // About the camera's own axes, orbiting the floor point the optical axis meets (a tilt
      // keeps the image centre where it was).
      const Eigen::Vector3d axis = c.rotation.transpose().col(2);
      const double along = axis.z() < -1e-6 ? -centre.z() / axis.z() : 0.0;
      const Eigen::Vector3d look = centre + along * axis;
      const Eigen::Matrix3d turned =
          Eigen::AngleAxisd(d, Eigen::Vector3d::Unit(i)).matrix() * c.rotation;
      centre = look + turned.transpose() * (c.rotation * (centre - look));
      c.rotation = turned;
    } else if (i < 5) {
      centre(i - 3) += d;
    } else if (i == 5) {
      centre.z() *= std::exp(d);
    } else {
      c.k1 = std::clamp(c.k1 + d, -0.8, 0.4);
    }
    c.translation_mm = -c.rotation * centre;
    return c;
  };
  sv.score = CameraScore(sv.camera, marks, dt, tau);
  for (int round = 0; round < 5; ++round) {
    bool improved = true;
    for (int pass = 0; pass < 6 && improved; ++pass) {
      improved = false;
      for (int i = 0; i < 7; ++i) {
        for (double sign : {1.0, -1.0}) {
          const camera::PinholeCamera c = with(i, sign * steps[i]);
          const double score = CameraScore(c, marks, dt, tau);
          if (score > sv.score) sv.camera = c, sv.score = score, improved = true;
        }
      }
    }
    for (double& s : steps) s *= 0.5;
  }
}

}  // namespace

LineDistance::LineDistance(const std::vector<LinePixel>& pixels, int width, int height)
    : w_(width), h_(height), d_(static_cast<size_t>(width) * height, 1e6f) {
  for (const LinePixel& p : pixels) {
    const int x = static_cast<int>(std::lround(p.pixel.x())),
              y = static_cast<int>(std::lround(p.pixel.y()));
    if (x >= 0 && y >= 0 && x < w_ && y < h_) d_[static_cast<size_t>(y) * w_ + x] = 0.0f;
  }
  // Two-pass chamfer distance (1, sqrt 2).
  const float r2 = static_cast<float>(std::numbers::sqrt2);
  auto at = [&](int x, int y) -> float& { return d_[static_cast<size_t>(y) * w_ + x]; };
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      float& v = at(x, y);
      if (x > 0) v = std::min(v, at(x - 1, y) + 1.0f);
      if (y > 0) {
        v = std::min(v, at(x, y - 1) + 1.0f);
        if (x > 0) v = std::min(v, at(x - 1, y - 1) + r2);
        if (x < w_ - 1) v = std::min(v, at(x + 1, y - 1) + r2);
      }
    }
  for (int y = h_ - 1; y >= 0; --y)
    for (int x = w_ - 1; x >= 0; --x) {
      float& v = at(x, y);
      if (x < w_ - 1) v = std::min(v, at(x + 1, y) + 1.0f);
      if (y < h_ - 1) {
        v = std::min(v, at(x, y + 1) + 1.0f);
        if (x < w_ - 1) v = std::min(v, at(x + 1, y + 1) + r2);
        if (x > 0) v = std::min(v, at(x - 1, y + 1) + r2);
      }
    }
}

double LineDistance::At(const Vec2& q) const {
  const int x = static_cast<int>(std::lround(q.x())), y = static_cast<int>(std::lround(q.y()));
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return 1e6;
  return d_[static_cast<size_t>(y) * w_ + x];
}

double CameraScore(const camera::PinholeCamera& camera, MarkSampler& marks, const LineDistance& dt,
                   double tau_px) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  // Points about 3 px apart where the camera sees them: the step from the mm per px at the
  // image centre.
  const Vec2 c(0.5 * (dt.width() - 1), 0.5 * (dt.height() - 1));
  const double scale = std::sqrt(std::max(1e-9, model.AreaScale(c, 0.0)));
  return Score(
      marks.Sample(3.0 * scale), 3.0, dt, [&](const Vec2& p) { return model.WorldToPixel(p, 0.0); },
      tau_px);
}

double CameraScore(const camera::PinholeCamera& camera, const FieldMarks& marks,
                   const LineDistance& dt, double tau_px) {
  MarkSampler sampler(marks);
  return CameraScore(camera, sampler, dt, tau_px);
}

namespace {

// The dominant direction (rad) of the line pixels modulo 90 deg: the mean of exp(4 i theta).
double DominantAngle(const std::vector<LinePixel>& pixels) {
  double sx = 0.0, sy = 0.0;
  for (const LinePixel& p : pixels) {
    const double t = 4.0 * std::atan2(p.direction.y(), p.direction.x());
    sx += std::cos(t);
    sy += std::sin(t);
  }
  return 0.25 * std::atan2(sy, sx);
}

// The straight lines of the frame along the image's a and b axes (turned by psi): the peaks of
// the pixels' positions across each axis, image-centred.
struct AxisPeaks {
  std::vector<double> a, b;
};
AxisPeaks FindAxisPeaks(const std::vector<LinePixel>& pixels, int width, int height, double psi) {
  const Vec2 c(0.5 * (width - 1), 0.5 * (height - 1));
  const double cp = std::cos(psi), sp = std::sin(psi);
  std::vector<double> along_a, along_b;  // positions across the image's a and b axes
  for (const LinePixel& p : pixels) {
    const Vec2 d = p.pixel - c;
    const Vec2 ab(cp * d.x() + sp * d.y(), -sp * d.x() + cp * d.y());
    const Vec2 dir(cp * p.direction.x() + sp * p.direction.y(),
                   -sp * p.direction.x() + cp * p.direction.y());
    if (std::abs(dir.y()) < kAxisTolerance) along_b.push_back(ab.y());  // a horizontal line
    if (std::abs(dir.x()) < kAxisTolerance) along_a.push_back(ab.x());  // a vertical line
  }
  const double extent = std::hypot(width, height);
  return {Peaks(along_a, extent), Peaks(along_b, extent)};
}

// The painted lines along the field's y axis (their x), along its x axis (their y), and the
// field's half size (mm) over its marks.
struct FieldAxes {
  std::vector<double> xs, ys;
  double size = 0.0;
};
FieldAxes AxesOf(const FieldMarks& marks) {
  FieldAxes f;
  auto add = [](std::vector<double>& v, double x) {
    if (std::none_of(v.begin(), v.end(), [&](double y) { return std::abs(x - y) < 1; }))
      v.push_back(x);
  };
  for (const MarkSegment& l : marks.segments) {
    const Vec2 d = l.to_mm - l.from_mm;
    if (std::abs(d.x()) < 1e-6 * d.norm()) add(f.xs, l.from_mm.x());
    if (std::abs(d.y()) < 1e-6 * d.norm()) add(f.ys, l.from_mm.y());
    f.size = std::max({f.size, l.from_mm.cwiseAbs().maxCoeff(), l.to_mm.cwiseAbs().maxCoeff()});
  }
  for (const MarkArc& a : marks.arcs) f.size = std::max(f.size, a.centre_mm.norm() + a.radius_mm);
  return f;
}

// One orientation k of the nadir view (internal.h's A_k): which field axis runs along the
// image's a axis, and the signs.
struct Orientation {
  int k = 0;
  bool a_is_x = true;
  double sign_a = 1.0, sign_b = -1.0;
  const std::vector<double>* wa = nullptr;
  const std::vector<double>* wb = nullptr;
};
Orientation OrientationOf(int k, const FieldAxes& f) {
  Orientation o;
  o.k = k;
  o.a_is_x = k % 2 == 0;
  o.sign_a = (k == 0 || k == 1) ? 1.0 : -1.0;
  o.sign_b = (k == 0 || k == 3) ? -1.0 : 1.0;
  o.wa = o.a_is_x ? &f.xs : &f.ys;
  o.wb = o.a_is_x ? &f.ys : &f.xs;
  return o;
}

// The scales (px/mm) the pairs of peaks along one axis give against pairs of field lines.
void PairScales(const std::vector<double>& pk, const std::vector<double>& w, double sign,
                double s_min, double s_max, std::vector<double>* scales) {
  for (size_t i = 0; i < pk.size(); ++i)
    for (size_t j = i + 1; j < pk.size(); ++j)
      for (size_t m = 0; m < w.size(); ++m)
        for (size_t n = 0; n < w.size(); ++n) {
          if (m == n) continue;
          const double s = (pk[j] - pk[i]) / (sign * (w[n] - w[m]));
          if (s >= s_min && s <= s_max) scales->push_back(s);
        }
}

// Scales to try: from pairs of peaks along either axis, and a log-spaced sweep; scales within 1%
// of a kept one add nothing the coarse score could tell apart.
std::vector<double> CandidateScales(const AxisPeaks& peaks, const Orientation& o, double s_min,
                                    double s_max) {
  std::vector<double> scales;
  PairScales(peaks.a, *o.wa, o.sign_a, s_min, s_max, &scales);
  PairScales(peaks.b, *o.wb, o.sign_b, s_min, s_max, &scales);
  for (double s = s_min; s <= s_max; s *= 1.03) scales.push_back(s);
  std::sort(scales.begin(), scales.end());
  std::vector<double> distinct;
  for (double s : scales)
    if (distinct.empty() || s > 1.01 * distinct.back()) distinct.push_back(s);
  return distinct;
}

// Candidate centres along one axis: a peak matched to a field line; none: the middle.
std::vector<double> Centres(const std::vector<double>& pk, const std::vector<double>& w,
                            double sign, double s) {
  std::vector<double> out;
  for (double p : pk)
    for (double v : w) out.push_back(v - p / (sign * s));
  if (out.empty()) out.push_back(0.0);
  return out;
}

// Every coarse hypothesis of one orientation, scored.
// The views with the field's middle as the centre along an axis whose peaks gave centres (a
// narrow view between the touch lines shows no line along that axis, while the arcs' tangents
// give peaks there that match no line in view) go to `middle`.
void CoarseViews(const AxisPeaks& peaks, const Orientation& o, double psi, double s_min,
                 double s_max, const FieldMarks& marks, const LineDistance& dt,
                 std::vector<ScoredView>* all, std::vector<ScoredView>* middle) {
  constexpr double kCoarseStepPx = 12.0;
  const Vec2 image_centre(0.5 * (dt.width() - 1), 0.5 * (dt.height() - 1));
  const double cp = std::cos(psi), sp = std::sin(psi);
  std::vector<Vec2> base;
  for (double s : CandidateScales(peaks, o, s_min, s_max)) {
    // The marks sampled once per scale, and mapped once through the views' common linear part
    // (orientation, psi, scale; no distortion): each view's centre only shifts them.
    const NadirView linear{o.k, psi, s, Vec2::Zero(), 0.0};
    base.clear();
    for (const Vec2& p : SampleMarks(marks, kCoarseStepPx / s, nullptr))
      base.push_back(image_centre + Apply(linear, p, dt.width(), cp, sp));
    std::vector<double> ca = Centres(peaks.a, *o.wa, o.sign_a, s);
    std::vector<double> cb = Centres(peaks.b, *o.wb, o.sign_b, s);
    const size_t na = ca.size(), nb = cb.size();
    if (!peaks.a.empty()) ca.push_back(0.0);
    if (!peaks.b.empty()) cb.push_back(0.0);
    for (size_t i = 0; i < ca.size(); ++i)
      for (size_t j = 0; j < cb.size(); ++j) {
        NadirView v{o.k, psi, s, o.a_is_x ? Vec2(ca[i], cb[j]) : Vec2(cb[j], ca[i]), 0.0};
        const Vec2 shift = -Apply(linear, v.centre_mm, dt.width(), cp, sp);
        (i < na && j < nb ? all : middle)
            ->push_back(ScoredView{v, ShiftedScore(base, shift, kCoarseStepPx, dt), {}});
      }
  }
}

// The best `count` hypotheses that differ in orientation, scale or centre, best first.
std::vector<ScoredView> BestDistinct(std::vector<ScoredView> all, size_t count) {
  std::sort(all.begin(), all.end(),
            [](const ScoredView& x, const ScoredView& y) { return x.score > y.score; });
  std::vector<ScoredView> best;
  for (const ScoredView& h : all) {
    if (best.size() >= count) break;
    const bool same = std::any_of(best.begin(), best.end(), [&](const ScoredView& b) {
      return b.view.k == h.view.k && std::abs(std::log(b.view.scale / h.view.scale)) < 0.05 &&
             (b.view.centre_mm - h.view.centre_mm).norm() * h.view.scale < 15.0;
    });
    if (!same) best.push_back(h);
  }
  return best;
}

void RefineView(ScoredView& b, const FieldMarks& field_marks, const LineDistance& dt, int width,
                int height) {
  MarkSampler marks(field_marks);
  b.score = ViewScore(b.view, marks, dt, 4.0, kCoarseTauPx);
  Refine(b, marks, dt, kCoarseTauPx);
  b.camera = PinholeOf(b.view, width, height);
  RefineCamera(b, marks, dt, kCoarseTauPx);
  RefineCamera(b, marks, dt, kTauPx);
}

constexpr double kMiddleGain = 1.5;

}  // namespace

std::vector<ScoredView> SearchViews(const std::vector<LinePixel>& pixels, int width, int height,
                                    const FieldMarks& marks, bool symmetric, int* hypotheses) {
  const LineDistance dt(pixels, width, height);
  const double psi = DominantAngle(pixels);
  const AxisPeaks peaks = FindAxisPeaks(pixels, width, height, psi);
  const FieldAxes axes = AxesOf(marks);
  const double s_min = width / (3.0 * axes.size), s_max = width / (0.15 * axes.size);
  std::vector<ScoredView> all, middle;
  for (int k = 0; k < (symmetric ? 2 : 4); ++k) {
    CoarseViews(peaks, OrientationOf(k, axes), psi, s_min, s_max, marks, dt, &all, &middle);
  }
  *hypotheses = static_cast<int>(all.size() + middle.size());
  std::vector<ScoredView> best = BestDistinct(std::move(all), 6);
  if (best.empty() || best.front().score <= 0.0) {
    throw InputError("no camera looking down at the field explains the " +
                     std::to_string(pixels.size()) + " line pixels (" +
                     std::to_string(peaks.a.size()) + " and " + std::to_string(peaks.b.size()) +
                     " straight lines along the image's two axes); expected a frame showing at "
                     "least two crossing field lines of the field");
  }
  for (ScoredView& b : best) RefineView(b, marks, dt, width, height);
  // The views centred on the field's middle replace them only when their best, refined, explains
  // clearly more (kMiddleGain times): where lines along both axes are in view the peaks' views
  // are the search's, as before.
  std::vector<ScoredView> mid = BestDistinct(std::move(middle), 2);
  for (ScoredView& b : mid) RefineView(b, marks, dt, width, height);
  const auto by_score = [](const ScoredView& x, const ScoredView& y) { return x.score > y.score; };
  std::sort(mid.begin(), mid.end(), by_score);
  if (!mid.empty() && mid.front().score > kMiddleGain * std::max(0.0, best.front().score)) {
    best.insert(best.end(), mid.begin(), mid.end());
  }
  std::sort(best.begin(), best.end(), by_score);
  return best;
}

}  // namespace patlab::calib::internal

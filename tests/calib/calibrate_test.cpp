// The camera fit against cameras it has never seen: random pinhole cameras with distortion look
// at the SSL 2008 field and at SSL standard robots; the visible field points, line and circle
// pixels and patch centres, with 0.3 px of noise, are fitted, and the fitted camera must map the
// whole image onto the floor and onto the robot tops as the true camera does.
#include "patlab/calib/calibrate.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/core/rng.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/calibration_input.h"
#include "patlab/formats/field_file.h"

namespace patlab::calib {
namespace {

constexpr double kNoisePx = 0.3;
using testing::kFrameHeight, testing::kFrameWidth;

// The 2009 field the seeds were chosen on: the shipped model less goal walls, posts, penalty marks.
Field Ssl2009() {
  Field f =
      formats::LoadField(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-2009.toml");
  std::erase_if(f.lines, [](const FieldLine& l) {
    return l.name.starts_with("goal_s") || l.name.starts_with("goal_back");
  });
  std::erase_if(f.points, [](const FieldPoint& p) {
    return p.name.starts_with("goal_") || p.name.starts_with("penalty_mark");
  });
  return f;
}

// Whether the true lens folds inside the image: a fit of it is refused (UnphysicalFitReason).
bool TruthFolds(const camera::CameraModel& truth) {
  const camera::PinholeCamera& c = truth.pinhole();
  const auto fold = DistortionFoldRadius(c.k1, c.k2);  // the corners are the farthest pixels
  const double corner = std::hypot(std::max(c.cx_px, kFrameWidth - c.cx_px) / c.fx_px,
                                   std::max(c.cy_px, kFrameHeight - c.cy_px) / c.fy_px);
  return fold && *fold < corner;
}

// A camera as SSL teams mount them: over one half of the field (its centre 1300-1750 mm from the
// halfway line), 2800-4500 mm up, the half field's width along the image's long side (yaw within
// 12 deg of that), tilted up to 15 deg about a random horizontal axis, a focal length that frames
// the half field (0.16-0.2 px per mm of floor), the principal point off centre by up to 15 px,
// and barrel distortion up to k1 = -0.35.
camera::PinholeCamera RandomCamera(RandomStream& rng) {
  camera::PinholeCamera c;
  const double height = rng.Uniform(2800.0, 4500.0);
  c.fx_px = c.fy_px = height * rng.Uniform(0.16, 0.2);
  c.cx_px = 389.5 + rng.Uniform(-15.0, 15.0);
  c.cy_px = 289.5 + rng.Uniform(-15.0, 15.0);
  c.k1 = rng.Uniform(-0.35, 0.0);
  const double side = rng.Uniform() < 0.5 ? -1.0 : 1.0;
  const double yaw = side * std::numbers::pi / 2 + rng.Uniform(-0.2, 0.2);
  const double tilt = rng.Uniform(0.0, 15.0) * std::numbers::pi / 180.0;
  const double tilt_axis = rng.Uniform(0.0, 2 * std::numbers::pi);
  Eigen::Matrix3d down;  // looking straight down, image right = world (cos yaw, sin yaw)
  down.col(0) = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
  down.col(1) = Eigen::Vector3d(std::sin(yaw), -std::cos(yaw), 0);
  down.col(2) = Eigen::Vector3d(0, 0, -1);
  const Eigen::Matrix3d tilt_r =
      Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(tilt_axis), std::sin(tilt_axis), 0))
          .toRotationMatrix();
  const Eigen::Matrix3d camera_to_world = tilt_r * down;
  const Eigen::Vector3d centre(side * rng.Uniform(1300, 1750), rng.Uniform(-200, 200), height);
  c.rotation = camera_to_world.transpose();
  c.translation_mm = -c.rotation * centre;
  return c;
}

struct Synthetic {
  CalibrationInput input;
  camera::CameraModel truth = camera::CameraModel::Pinhole({});
};

std::optional<Vec2> Observe(const camera::CameraModel& cam, const Vec2& world, double h,
                            RandomStream& rng) {
  const auto px = cam.WorldToPixel(world, h);
  if (!px || px->x() < 2 || px->y() < 2 || px->x() > kFrameWidth - 3 || px->y() > kFrameHeight - 3)
    return std::nullopt;
  const Vec2 noisy = *px + kNoisePx * Vec2(rng.Normal(), rng.Normal());
  // A pixel the lens cannot show (pushed past the fold of its distortion by the noise) is not an
  // observation.
  if (!cam.PixelToWorld(noisy, h)) return std::nullopt;
  return noisy;
}

void ObserveField(const Field& field, const camera::CameraModel& cam, RandomStream& rng,
                  CalibrationInput& in) {
  for (const FieldPoint& p : field.points)
    if (const auto px = Observe(cam, p.at_mm, 0.0, rng))
      in.points.push_back({p.name, *px, p.at_mm, 0.0, {}});
  for (const FieldLine& l : field.lines) {
    LineObservation o{l.name, l.from_mm, l.to_mm, 0.0, {}, {}};
    for (int k = 0; k <= 40; ++k)
      if (const auto px = Observe(cam, l.from_mm + (k / 40.0) * (l.to_mm - l.from_mm), 0, rng))
        o.pixels.push_back(*px);
    if (o.pixels.size() >= 2) in.lines.push_back(o);
  }
  for (const FieldCircle& c : field.circles) {
    CircleObservation o{c.name, c.centre_mm, c.radius_mm, 0.0, {}, {}};
    for (int k = 0; k < 24; ++k) {
      const double phi = 2 * std::numbers::pi * k / 24;
      if (const auto px =
              Observe(cam, c.centre_mm + c.radius_mm * Vec2(std::cos(phi), std::sin(phi)), 0, rng))
        o.pixels.push_back(*px);
    }
    if (o.pixels.size() >= 2) in.circles.push_back(o);
  }
}

// Robots of the SSL standard pattern on 150 mm tops, wherever the camera sees the floor.
void ObserveRobots(const camera::CameraModel& cam, RandomStream& rng, CalibrationInput& in) {
  const Pattern pattern = testing::ShippedPattern("ssl-standard");
  for (int attempt = 0; attempt < 60 && in.patterns.size() < 4; ++attempt) {
    const Vec2 px(rng.Uniform(60, kFrameWidth - 60), rng.Uniform(60, kFrameHeight - 60));
    const auto at = cam.PixelToWorld(px, 150.0);
    if (!at) continue;
    const Pose2 pose{at->x(), at->y(), rng.Uniform(-3.0, 3.0)};
    PatternObservation o{pattern.name, pattern, 150.0, {}, {}};
    int seen = 0;
    for (const Patch& patch : pattern.patches) {
      o.pixels.push_back(Observe(cam, pose.Apply(patch.position_mm), 150.0, rng));
      seen += o.pixels.back().has_value();
    }
    if (seen >= 3) in.patterns.push_back(o);
  }
}

// `realisation` >= 0: the same camera as `seed`, seen with other noise (and robot poses).
Synthetic MakeSynthetic(uint64_t seed, bool robots, int realisation = -1) {
  RandomStream rng(seed, 0, 0);
  Synthetic s;
  s.truth = camera::CameraModel::Pinhole(RandomCamera(rng));
  if (realisation >= 0) rng = RandomStream(seed, 1, static_cast<uint64_t>(realisation));
  s.input.image_width_px = kFrameWidth;
  s.input.image_height_px = kFrameHeight;
  s.input.loc = FileLoc{"synthetic", 0};
  ObserveField(Ssl2009(), s.truth, rng, s.input);
  // A user clicks points they can place: the centre, the corners and defense-area corners in
  // view, so that the start has four known points no three on a line (FitCamera refuses less).
  if (robots) ObserveRobots(s.truth, rng, s.input);
  return s;
}

// Calls f(pixel, point) for the pixels of a 20 px grid that the true camera puts on the field
// (within 100 mm of its lines) on the plane at `height`, with that point. Outside it the fit
// extrapolates the lens beyond anything it observed.
template <typename F>
void ForEachFieldPixel(const camera::CameraModel& truth, double height, F f) {
  for (int v = 10; v < kFrameHeight; v += 20) {
    for (int u = 10; u < kFrameWidth; u += 20) {
      const auto b = truth.PixelToWorld(Vec2(u, v), height);
      if (b && std::abs(b->x()) <= 3125 && std::abs(b->y()) <= 2125) f(Vec2(u, v), *b);
    }
  }
}

// The distances (mm) between where the fitted and the true camera put the field's pixels
// (ForEachFieldPixel) on the plane at `height`: RMS and worst.
std::pair<double, double> MappingError(const camera::CameraModel& fitted,
                                       const camera::CameraModel& truth, double height) {
  double worst = 0.0, sum2 = 0.0;
  int n = 0;
  ForEachFieldPixel(truth, height, [&](const Vec2& pixel, const Vec2& at) {
    const auto a = fitted.PixelToWorld(pixel, height);
    const double d = a ? (*a - at).norm() : std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
    sum2 += d * d;
    ++n;
  });
  EXPECT_GT(n, 100);
  return {std::sqrt(sum2 / n), worst};
}

// e' C^-1 e for a row-major 2x2 covariance C.
double Mahalanobis2(const std::array<double, 4>& c, const Vec2& e) {
  const double det = c[0] * c[3] - c[1] * c[2];
  return (c[3] * e.x() * e.x() - 2 * c[1] * e.x() * e.y() + c[0] * e.y() * e.y()) / det;
}

// The error of one observation on the floor: the pixel noise over the truth camera's scale
// (px per mm at the image centre). Fitted to a hundred or more pixels, a camera seen from above
// with its focal length determined maps the observed floor to within twice that on average.
double NoiseMm(const camera::CameraModel& truth, double height) {
  return kNoisePx * std::sqrt(truth.AreaScale(Vec2(kFrameWidth / 2.0, kFrameHeight / 2.0), height));
}

// The residuals are the noise: the sum of squares over sigma^2 is chi-square with 2N - p degrees
// of freedom for N pixels and p fitted numbers (each line or circle pixel's free position absorbs
// the noise along the line); within 4 of its standard deviations sqrt(2 (2N - p)).
void ExpectNoiseResiduals(const CalibrationFit& fit) {
  const double dof = 2.0 * fit.observations - fit.parameters;
  const double chi2 = fit.observations * fit.rms_px * fit.rms_px / (kNoisePx * kNoisePx);
  EXPECT_NEAR(chi2, dof, 4 * std::sqrt(2 * dof));
}

// The pixels where the input saw something on the plane at `height`, mapped by both cameras:
// RMS distance (mm). Only the observed heights' mapping is what the data determine.
double ObservedError(const CalibrationInput& in, const camera::CameraModel& fitted,
                     const camera::CameraModel& truth, double height) {
  double sum2 = 0.0;
  int n = 0;
  auto add = [&](const Vec2& px, double h) {
    if (h != height) return;
    const auto a = fitted.PixelToWorld(px, h), b = truth.PixelToWorld(px, h);
    sum2 += a && b ? (*a - *b).squaredNorm() : std::numeric_limits<double>::infinity();
    ++n;
  };
  for (const auto& p : in.points) add(p.pixel, p.height_mm);
  for (const auto& l : in.lines)
    for (const Vec2& px : l.pixels) add(px, l.height_mm);
  for (const auto& c : in.circles)
    for (const Vec2& px : c.pixels) add(px, c.height_mm);
  for (const auto& p : in.patterns)
    for (const auto& px : p.pixels)
      if (px) add(*px, p.height_mm);
  EXPECT_GT(n, 0);
  return std::sqrt(sum2 / n);
}

// The largest squared Mahalanobis distance, over MappingError's grid on the plane at `height`,
// between where the fitted and the true camera put a pixel, in the fit's own covariance there
// (MappingCovariance). To first order the errors at all pixels are one linear image of the camera
// parameters' error d, so each is at most d' C^-1 d, chi-square with as many degrees of freedom as
// free camera parameters (Cauchy-Schwarz).
double WorstMahalanobis2(const CalibrationFit& fit, const camera::CameraModel& truth,
                         double height) {
  const camera::CameraModel fitted = camera::CameraModel::Pinhole(fit.camera);
  double worst = 0.0;
  ForEachFieldPixel(truth, height, [&](const Vec2& pixel, const Vec2& at) {
    const auto a = fitted.PixelToWorld(pixel, height);
    const auto c = MappingCovariance(fit, pixel, height);
    worst = std::max(worst,
                     a && c ? Mahalanobis2(*c, *a - at) : std::numeric_limits<double>::infinity());
  });
  return worst;
}

// scipy.stats.chi2.ppf(0.9999, 10): the bound of WorstMahalanobis2 for 10 free camera numbers.
constexpr double kChi2TenDof9999 = 35.564;

// The fit's nuisance unknowns: a position per line or circle pixel, a planar pose per pattern.
int FittedNuisance(const CalibrationInput& in) {
  int n = 3 * static_cast<int>(in.patterns.size());
  for (const auto& l : in.lines) n += static_cast<int>(l.pixels.size());
  for (const auto& c : in.circles) n += static_cast<int>(c.pixels.size());
  return n;
}

// A fitted parameter within 4 of its standard error of the truth, or reported as undetermined
// (NaN: the covariance is singular, and the report prints "undetermined by these data").
void ExpectWithinItsError(double fitted, double truth, double se) {
  if (std::isnan(se)) return;
  EXPECT_NEAR(fitted, truth, 4 * se);
}

// Seeds whose camera sees four known field points no three on a line (FitCamera refuses less:
// DataThatCannotDetermineACameraAreRefused); the others see only the halfway line's points.
// Seeds whose true lens folds inside the image are refused too (TruthFolds).
bool Usable(const Synthetic& s) {
  try {
    FitCamera(s.input);
    return true;
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (TruthFolds(s.truth)) {
      EXPECT_NE(what.find("the fitted camera is not usable"), std::string::npos) << what;
    } else {
      EXPECT_NE(what.find("no four of the known points"), std::string::npos) << what;
    }
    return false;
  }
}

// What the data determine, checked against the truth: the floor over the whole field, and every
// fitted intrinsic parameter within 4 of its reported standard error (so the reported uncertainty
// is honest too). A robot of unknown pose tells the fit the scale of its plane, not where the
// plane lies: the robot tops separate the focal length from the camera's height, and the
// principal point from a tilt, only weakly, and how well the 150 mm plane is mapped is what
// those standard errors say, not a fixed number (AMeasuredCameraHeight... pins it down).
TEST(Calibrate, RecoversRandomCamerasFromFieldAndRobots) {
  int fitted_cameras = 0;
  for (uint64_t seed = 1; seed <= 13; ++seed) {  // some true lenses fold: refused, skipped
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Synthetic s = MakeSynthetic(seed, /*robots=*/true);
    if (!Usable(s)) continue;
    ++fitted_cameras;
    const CalibrationFit fit = FitCamera(s.input);
    const camera::CameraModel fitted = camera::CameraModel::Pinhole(fit.camera);
    const camera::PinholeCamera& t = s.truth.pinhole();
    ExpectNoiseResiduals(fit);
    ASSERT_EQ(fit.parameters - FittedNuisance(s.input), 10);  // f, cx, cy, k1 and the pose
    EXPECT_LT(WorstMahalanobis2(fit, s.truth, 0.0), kChi2TenDof9999);
    EXPECT_LT(WorstMahalanobis2(fit, s.truth, 150.0), kChi2TenDof9999);
    const auto& se = fit.standard_error;
    ExpectWithinItsError(fit.camera.fx_px, t.fx_px, se[0]);
    ExpectWithinItsError(fit.camera.cx_px, t.cx_px, se[2]);
    ExpectWithinItsError(fit.camera.cy_px, t.cy_px, se[3]);
    ExpectWithinItsError(fit.camera.k1, t.k1, se[4]);
    ASSERT_EQ(fit.planes.size(), 2u);
    EXPECT_EQ(fit.planes[1].height_mm, 150.0);
  }
  EXPECT_GE(fitted_cameras, 7);
}

TEST(Calibrate, TheMappingCovarianceIsTheSpreadOfRefits) {
  // One camera seen 50 times with fresh noise (and robots elsewhere): at the field pixel where the
  // first fit is least certain, the squared Mahalanobis distance of each fit's error in its own
  // MappingCovariance is chi-square with 2 degrees of freedom if the covariance is right, so the
  // mean of 50 lies within [1.198, 3.063] (scipy: chi2.ppf(0.0005 and 0.9995, 100) / 50). A
  // covariance twice too large or too small fails.
  const camera::CameraModel truth = MakeSynthetic(1, true).truth;
  const CalibrationFit first = FitCamera(MakeSynthetic(1, true, 0).input);
  Vec2 pixel = Vec2::Zero();
  double widest = 0.0;
  ForEachFieldPixel(truth, 0.0, [&](const Vec2& px, const Vec2&) {
    const auto c = MappingCovariance(first, px, 0.0);
    ASSERT_TRUE(c.has_value());
    if ((*c)[0] + (*c)[3] > widest) widest = (*c)[0] + (*c)[3], pixel = px;
  });
  const Vec2 at = *truth.PixelToWorld(pixel, 0.0);
  constexpr int kFits = 50;
  double sum = 0.0;
  for (int k = 0; k < kFits; ++k) {
    const CalibrationFit fit = FitCamera(MakeSynthetic(1, true, k).input);
    const auto c = MappingCovariance(fit, pixel, 0.0);
    const auto mapped = camera::CameraModel::Pinhole(fit.camera).PixelToWorld(pixel, 0.0);
    ASSERT_TRUE(c && mapped);
    sum += Mahalanobis2(*c, *mapped - at);
  }
  EXPECT_GT(sum / kFits, 1.198) << "at pixel " << pixel.transpose();
  EXPECT_LT(sum / kFits, 3.063) << "at pixel " << pixel.transpose();
  EXPECT_GT(std::sqrt(widest), 1.0);  // a corner the fit extrapolates to: mm, not micrometres
}

TEST(Calibrate, TheFloorAloneMapsTheFloorAndSaysWhatItCannotKnow) {
  // A camera looking nearly straight down sees the floor the same from any height with the focal
  // length scaled alike: the floor is mapped; the focal length is either right within its
  // standard error or reported as not determined.
  for (uint64_t seed = 11; seed <= 18; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Synthetic s = MakeSynthetic(seed, /*robots=*/false);
    if (!Usable(s)) continue;
    const CalibrationFit fit = FitCamera(s.input);
    ExpectNoiseResiduals(fit);
    // Either the observed floor is mapped within twice one observation's error, or the report
    // says the fitted lens folds over observed pixels (one of these floor-only fits does).
    const std::string report = FitReportText(s.input, fit);
    if (report.find("lie beyond the fold") == std::string::npos) {
      EXPECT_LT(ObservedError(s.input, camera::CameraModel::Pinhole(fit.camera), s.truth, 0.0),
                2.0 * NoiseMm(s.truth, 0.0));
    }
    const bool warned =
        FitReportText(s.input, fit).find("warning: the focal length is not determined") !=
        std::string::npos;
    if (!warned) {
      EXPECT_NEAR(fit.camera.fx_px, s.truth.pinhole().fx_px, 4 * fit.standard_error[0]);
    }
  }
}

TEST(Calibrate, AMeasuredCameraHeightDeterminesTheFocalLength) {
  for (uint64_t seed = 11; seed <= 18; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Synthetic s = MakeSynthetic(seed, /*robots=*/false);
    if (!Usable(s)) continue;
    const camera::PinholeCamera& t = s.truth.pinhole();
    const double true_height = (-t.rotation.transpose() * t.translation_mm).z();
    s.input.options.camera_height_mm = true_height + 5.0;  // measured with a tape
    s.input.options.camera_height_sd_mm = 10.0;
    const CalibrationFit fit = FitCamera(s.input);
    ExpectNoiseResiduals(fit);
    // On average over the field (some of these cameras see few lines, and extrapolate the
    // lens to a far corner by 10 mm or more).
    EXPECT_LT(MappingError(camera::CameraModel::Pinhole(fit.camera), s.truth, 0.0).first,
              2.0 * NoiseMm(s.truth, 0.0));
    EXPECT_NEAR(fit.camera_centre_mm.z(), true_height, 30.0);
    EXPECT_NEAR(fit.camera.fx_px, t.fx_px, 4 * fit.standard_error[0]);
    EXPECT_LT(fit.standard_error[0], 0.02 * fit.camera.fx_px);
  }
}

TEST(Calibrate, TheWrittenFileIsTheFittedCamera) {
  const Synthetic s = MakeSynthetic(3, true);
  CalibrationInput in = s.input;
  in.default_height_mm = 150;
  in.class_height_mm["orange"] = 21.5;
  const CalibrationFit fit = FitCamera(in);
  const camera::Calibration cal = formats::ParseCalibration(CalibrationFileText(in, fit), "fit");
  EXPECT_EQ(cal.image_width_px, kFrameWidth);
  EXPECT_EQ(cal.default_height_mm, 150.0);
  EXPECT_EQ(cal.HeightOf("orange"), 21.5);
  EXPECT_LT(MappingError(cal.camera, camera::CameraModel::Pinhole(fit.camera), 150.0).second, 1e-6);
  // The residual rows: every observed plane (0 and 150 mm) with its measured residual, and the
  // class height 21.5 mm, where nothing was observed, converted from the pixel residuals.
  ASSERT_EQ(fit.planes.size(), 2u);
  ASSERT_EQ(cal.residuals.size(), 3u);
  EXPECT_EQ(cal.residuals[0].height_mm, 0.0);
  EXPECT_NEAR(cal.residuals[0].rms_mm, fit.planes[0].rms_mm, 5e-4);
  EXPECT_NEAR(cal.residuals[0].worst_mm, fit.planes[0].worst_mm, 5e-4);
  EXPECT_TRUE(cal.residuals[0].measured);
  EXPECT_EQ(cal.residuals[1].height_mm, 21.5);
  EXPECT_FALSE(cal.residuals[1].measured);
  EXPECT_EQ(cal.residuals[2].height_mm, 150.0);
  EXPECT_NEAR(cal.residuals[2].rms_mm, fit.planes[1].rms_mm, 5e-4);
  EXPECT_EQ(cal.ResidualRmsMm(cal.default_height_mm), cal.residuals[2].rms_mm);
  // The converted row: each pixel's px residual times the mm per px of the 21.5 mm plane, which
  // lies between the two observed planes' scales (the camera is a few metres up).
  double sum2 = 0.0;
  for (const ObservationResidual& r : fit.residuals) {
    const double mm = r.px * std::sqrt(cal.camera.AreaScale(r.pixel, 21.5));
    sum2 += mm * mm;
  }
  EXPECT_NEAR(cal.residuals[1].rms_mm, std::sqrt(sum2 / fit.residuals.size()), 5e-4);
}

TEST(Calibrate, ReportsEveryPixelAndTheWorst) {
  const Synthetic s = MakeSynthetic(1, true);
  const CalibrationFit fit = FitCamera(s.input);
  size_t pixels = s.input.points.size();
  for (const auto& l : s.input.lines) pixels += l.pixels.size();
  for (const auto& c : s.input.circles) pixels += c.pixels.size();
  for (const auto& p : s.input.patterns)
    for (const auto& px : p.pixels) pixels += px.has_value();
  EXPECT_EQ(fit.residuals.size(), pixels);
  EXPECT_EQ(fit.observations, static_cast<int>(pixels));
  double worst = 0.0;
  for (const auto& r : fit.residuals) worst = std::max(worst, r.px);
  EXPECT_EQ(fit.worst_px, worst);
  const std::string report = FitReportText(s.input, fit);
  EXPECT_NE(report.find("worst pixels:"), std::string::npos);
  EXPECT_NE(report.find("(held fixed)"), std::string::npos);  // k2 and the aspect
}

TEST(Calibrate, AnOutlierIsTamedByTheHuberLoss) {
  uint64_t seed = 6;  // the first camera from 6 on whose own lens does not fold in the image
  while (TruthFolds(MakeSynthetic(seed, true).truth)) ++seed;
  Synthetic s = MakeSynthetic(seed, true);
  Vec2& px = s.input.lines.front().pixels.front();  // mis-clicked 40 px towards the centre
  px += 40.0 * (Vec2(390, 290) - px).normalized();
  double plain = std::numeric_limits<double>::infinity();  // refused: bent past a fold
  try {
    plain = MappingError(camera::CameraModel::Pinhole(FitCamera(s.input).camera), s.truth, 0).first;
  } catch (const InputError&) {
  }
  s.input.options.huber_px = 1.0;
  const double robust =
      MappingError(camera::CameraModel::Pinhole(FitCamera(s.input).camera), s.truth, 0.0).first;
  EXPECT_LT(robust, 0.5 * plain);
  EXPECT_LT(robust, 1.5);
}

CalibrationInput Parse(const std::string& text) {
  return formats::ParseCalibrationInput(text, "in.toml",
                                        std::string(PATLAB_SOURCE_DIR) + "/experiments");
}

std::string Points(const std::vector<std::pair<Vec2, Vec2>>& pts) {
  std::string out = "image_size_px = [780, 580]\n";
  for (const auto& [px, w] : pts)
    out += "[[point]]\nworld_mm = [" + std::to_string(w.x()) + ", " + std::to_string(w.y()) +
           "]\npixel = [" + std::to_string(px.x()) + ", " + std::to_string(px.y()) + "]\n";
  return out;
}

TEST(Calibrate, DataThatCannotDetermineACameraAreRefused) {
  EXPECT_INPUT_ERROR(FitCamera(Parse(Points({{{1, 1}, {0, 0}}, {{2, 2}, {10, 0}}}))),
                     "in.toml: the input has 2 known points on its best-covered plane; expected "
                     "at least 4 [[point]] tables on one plane height (the fit starts from their "
                     "homography)");
  EXPECT_INPUT_ERROR(
      FitCamera(Parse(
          Points({{{1, 1}, {0, 0}}, {{2, 2}, {10, 0}}, {{3, 3}, {20, 0}}, {{4, 4}, {30, 0}}}))),
      "in.toml:2: no four of the known points on the plane at 0 mm are free of three on a line; "
      "expected at least 4 points no three of which lie on one line (e.g. field corners and the "
      "centre)");
  EXPECT_INPUT_ERROR(
      FitCamera(Parse(
          Points({{{1, 1}, {0, 0}}, {{800, 2}, {10, 0}}, {{3, 3}, {20, 5}}, {{4, 4}, {30, 0}}}))),
      "in.toml:5: pixel (800, 2) is outside the 780x580 image; expected pixel coordinates "
      "within it");
  EXPECT_INPUT_ERROR(
      FitCamera(Parse(Points({{{100, 100}, {0, 0}},
                              {{500, 100}, {1000, 0}},
                              {{500, 400}, {1000, 800}},
                              {{100, 400}, {0, 800}}}))),
      "in.toml: 4 observed pixels give 8 equations for 10 unknowns; expected more points, line "
      "or circle pixels");
}

}  // namespace
}  // namespace patlab::calib

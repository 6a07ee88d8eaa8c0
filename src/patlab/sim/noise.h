// Patch noise models of the Monte-Carlo engine. One parametrisation covers four models (isotropic,
// anisotropic, outliers, common jitter); every spread is a multiple of the swept patch sigma, so
// a sweep scales them together.
//
// For trial t with true patch positions P_i (world frame) the observed positions are
//
//   V_i = P_i + e_i + c
//   e_i = sigma (z_ix, r z_iy)        with probability 1 - p   (r = sigma_y_ratio: anisotropic)
//   e_i = sigma k (z_ix, z_iy)        with probability p       (k = outlier_sigma_ratio: outliers)
//   c   = sigma g (z_cx, z_cy)        once per trial           (g = common_sigma_ratio: jitter)
//
// with all z standard normals, independent between patches and trials. The paper's model
// (section IV) is the isotropic Gaussian: sigma_y_ratio = 1, p = 0, common = 0; sigma is then
// "the patch positional standard deviation" along each axis.
//
// Four camera-level models, in absolute units (they do not scale with sigma), applied
// in this order on top of the above (in detect mode through FrameCameraNoise below, a frame
// being one trial):
//
//   correlated noise   e = L e'  per axis, L L^T = C, C_ij = exp(-|p_i - p_j| / correlation_length)
//                      (p_i the model positions; e' the independent errors above): each patch
//                      keeps its variance, neighbours move together (correlation_length_mm > 0)
//   colour-edge bias   V_i += (key_shift_x_mm or id_shift_x_mm, 0): a fixed shift along the
//                      image rows (world x) by the patch's colour class, the key colour (team
//                      blue/yellow) or the ID colours (pink/green): 4:2:2 chroma is sampled at
//                      half the horizontal resolution, so colour edges move along x
//   camera jitter      V_i = (1 + eps) R(phi) V_i about the camera axis (world origin, the field
//                      centre), phi = rotation_jitter_rad z_r, eps = 1e-6 scale_jitter_ppm z_s:
//                      a camera that twists about its optical axis and bobs in height (a height
//                      change dh at height h scales the image by about -dh / h)
//
// z_r, z_s standard normals once per trial. Each has a first-order prediction
// (noise_prediction.h).
//
// The known-correspondence kernel (batch.cpp) evaluates these formulas vectorised over a batch
// of trials; PatchError and CommonOffset below are the scalar form, one draw at a time from a
// RandomStream, used by the whole-frame (detect) runner through PatchNoise::perturb.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/rng.h"
#include "patlab/estimate/gls.h"

namespace patlab::sim {

struct NoiseModel {
  double sigma_y_ratio = 1.0;         // sigma_y / sigma_x in the world frame (anisotropic); > 0
  double common_sigma_ratio = 0.0;    // std of the per-trial offset shared by all patches / sigma
  double outlier_probability = 0.0;   // probability that a patch is an outlier, in [0, 1)
  double outlier_sigma_ratio = 10.0;  // an outlier's isotropic std / sigma; > 0
  // Camera-level models (above); all 0 = off, and then a point's random streams and results are
  // those of the four models before them (point_key.h adds these fields only when non-zero).
  double rotation_jitter_rad = 0.0;    // std of the per-trial camera roll phi; in [0, 0.1]
  double scale_jitter_ppm = 0.0;       // std of the per-trial scale eps, parts per million;
                                       // in [0, 1e5] (330 ppm ~ 1 mm of height at 3 m)
  double correlation_length_mm = 0.0;  // L of exp(-d / L) between patch errors; >= 0, 0 = none
  double key_shift_x_mm = 0.0;         // colour-edge bias of the key patch along x; |.| <= 100
  double id_shift_x_mm = 0.0;          // colour-edge bias of every other patch along x

  // True when any camera-level model is on.
  bool HasCameraModels() const {
    return rotation_jitter_rad != 0.0 || scale_jitter_ppm != 0.0 || correlation_length_mm != 0.0 ||
           key_shift_x_mm != 0.0 || id_shift_x_mm != 0.0;
  }

  bool IsIsotropicGaussian() const {
    return sigma_y_ratio == 1.0 && common_sigma_ratio == 0.0 && outlier_probability == 0.0 &&
           !HasCameraModels();
  }
  // True when the patch errors are jointly Gaussian with a covariance known up to sigma (the
  // isotropic, anisotropic, common-offset and correlated models): no outliers, no camera roll or
  // scale jitter, no colour-edge bias.
  bool IsGaussian() const {
    return outlier_probability == 0.0 && rotation_jitter_rad == 0.0 && scale_jitter_ppm == 0.0 &&
           key_shift_x_mm == 0.0 && id_shift_x_mm == 0.0;
  }
  // The Gaussian part (anisotropy, correlation, common offset) as estimate/gls.h takes it: the
  // covariance "ml" weights by whenever it is not least squares (GaussianNoise::IsLeastSquares).
  estimate::GaussianNoise GaussianPart() const {
    return {sigma_y_ratio, correlation_length_mm, common_sigma_ratio};
  }
  // The per-axis std, averaged over the two axes, of an independent patch error per unit sigma:
  // sqrt(((1 - p)(1 + r^2) / 2 + p k^2)). Linear estimators' first-order std scale with it.
  double EffectiveSigmaRatio() const;
  // Human-readable name of the model ("isotropic", "anisotropic+common", ...).
  std::string Describe() const;

  // One patch's independent error e_i (mm) at patch sigma `sigma_mm`. Draws, in this order: two
  // normals (z_ix, z_iy), then one uniform deciding "outlier" only when outlier_probability > 0.
  Vec2 PatchError(double sigma_mm, RandomStream& rng) const;
  // The common offset c (mm), once per trial (a whole frame in detect mode): two normals when
  // common_sigma_ratio > 0 and sigma_mm > 0, else zero and no draws.
  Vec2 CommonOffset(double sigma_mm, RandomStream& rng) const;
};

// The camera-level models of one whole frame in detect mode (GenerateDetectFrame,
// detect_runner.h), applied patch by patch as the scene draws them: every robot's patches come
// in pattern order, each with its independent error e'_i already drawn, and get
//   e_i = sum_{j <= i} L_ij e'_j  (L the Cholesky factor of exp(-|p_i - p_j| / L), patch order,
//                                  the same mixing as the known-mode kernel),
//   + the key or ID shift along world x, then the frame's camera roll and scale about the world
//   origin (phi, eps drawn once per frame, in that order, from the stream given).
// The frame is one "trial" of the formulas above. Not thread-safe: one per frame.
inline constexpr uint32_t kDetectCameraStream = 0x64636d72;  // "dcmr": a frame's roll and scale
class FrameCameraNoise {
 public:
  // `positions_mm`: the pattern's model positions in patch order; `key_index` its key patch
  // (-1: none). Draws phi and eps from `rng` only when their std is > 0.
  FrameCameraNoise(const NoiseModel& noise, const std::vector<Vec2>& positions_mm, int key_index,
                   RandomStream& rng);
  // The observed position of the next patch (pattern order, robot after robot): `base_mm` is the
  // true position plus the frame's common offset, `independent_mm` the patch's e'_i.
  Vec2 Next(const Vec2& base_mm, const Vec2& independent_mm);

 private:
  const NoiseModel& noise_;
  int num_patches_ = 0;
  int key_index_ = -1;
  int next_ = 0;                   // patch index of the next call
  std::vector<double> factor_;     // L, row-major n x n (empty: independent)
  std::vector<Vec2> independent_;  // this robot's e'_j so far
  double cos_ = 1.0, sin_ = 0.0;   // (1 + eps) (cos phi, sin phi)
};

// The one place the noise model is checked (core/options.h), fields named as the keys of an
// experiment's [noise] table: sigma_y_ratio a finite number > 0, common_sigma_ratio a finite
// number >= 0, outlier_probability in [0, 1) (1 would make every patch an outlier),
// outlier_sigma_ratio a finite number > 0, rotation_jitter_rad in [0, 0.1] (small angles),
// scale_jitter_ppm in [0, 1e5], correlation_length_mm a finite number >= 0, key_shift_x_mm and
// id_shift_x_mm in [-100, 100].
std::vector<OptionsProblem> Check(const NoiseModel& noise);
void Validate(const NoiseModel& noise);

}  // namespace patlab::sim

// Which error mechanisms, with which magnitudes, reproduce the paper's
// section-II white patches (Table I) and its section-IV Butterfly (sigma_x 0.3766, sigma_y
// 0.3432 mm, sigma_theta 0.0070 rad) at once -- an estimation problem with confidence intervals.
//
// Data: reported stds d_i with sampling standard errors se_i (Table I: from its 95% intervals,
// the Butterfly: chi-square on 5 x 2570 samples; both widened by sqrt(tau), tau the variance
// inflation of autocorrelated frames, stats/effective_n.h).
// Model (first order, noise_prediction.h, here per axis on the section-II track): each datum's
// variance as the paper's estimator sees it is
//   v_i = q_i^2 + k^2 sum_j a_ij m_j^2
// with q_i the pixel quantisation of that subject through the paper's smoothing estimate
// (measured by patlab track, results/track_quantisation/table1.csv: fixed, not fitted), k the
// smoothing estimate's white-noise factor (stats::ResidualStdFactor, 0.974 at sigma 10: every
// mechanism below is independent between frames) and m_j the mechanism magnitudes:
//   independent_x_mm, independent_y_mm  per-patch Gaussian along world x (the travel, image
//                                       rows) and y: every patch, white or coloured
//   common_mm        per-frame translation of the whole image (per axis)
//   roll_mrad        per-frame camera roll about the optical axis: moves a subject at T by
//                    phi J T (x error -phi T_y, y error phi T_x) and the pattern angle by phi
//   scale_ppm        per-frame scale (height bob): moves a subject at T by eps T
//   correlated_mm    per-patch noise with correlation exp(-d / correlation_length_mm) between
//                    patches (a single patch sees its full variance; a pattern averages less)
//   colour_mm        extra independent per-patch noise of coloured patches (the Butterfly's;
//                    Table I's are white): colour segmentation through Bayer and 4:2:2
// The coefficients a_ij come from the track geometry (T_x uniform over the travel, T_y over the
// lateral offsets: E[T_x^2] = travel^2 / 12, E[T_y^2] = lateral^2 / 12) and, for the Butterfly,
// from the fast estimator's Jacobian (estimate::EstimatorJacobian) averaged over heading.
// Not in the fit, because stds cannot see them: the colour-edge bias (a fixed shift at a run's
// constant heading, removed with the run's mean) and the outlier mixture (it scales every
// patch's std by sqrt(1 - p + p k^2), exactly as a larger independent sigma).
//
// Fit: -2 log L = sum_i (d_i - sqrt(v_i))^2 / s_i^2 + log s_i^2, s_i^2 = se_i^2 (+ delta^2 for
// Table I rows), delta the spread between patch sizes the size-independent mechanisms cannot
// express: estimated first on Table I alone (AddTable1Discrepancy), then held fixed in the
// joint fit (fitted jointly, it would let the fit discount Table I as a whole). Minimised with
// NLopt BOBYQA in bounds from several starts; profile likelihood intervals (-2 delta log L <= 3.84)
// per magnitude, a parametric bootstrap (correlations of the estimates) and an identifiability
// verdict per magnitude.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/options.h"
#include "patlab/estimate/estimators.h"

namespace patlab::paper {

enum class Mechanism { kIndependentX, kIndependentY, kCommon, kRoll, kScale, kCorrelated, kColour };
inline constexpr int kNumMechanisms = 7;
inline constexpr EnumNames<Mechanism, kNumMechanisms> kMechanismNames{{{
    {Mechanism::kIndependentX, "independent_x_mm"},
    {Mechanism::kIndependentY, "independent_y_mm"},
    {Mechanism::kCommon, "common_mm"},
    {Mechanism::kRoll, "roll_mrad"},
    {Mechanism::kScale, "scale_ppm"},
    {Mechanism::kCorrelated, "correlated_mm"},
    {Mechanism::kColour, "colour_mm"},
}}};
using Magnitudes = std::array<double, kNumMechanisms>;

// The experiment's geometry: the assumptions the paper does not state are all here.
struct NoiseFitGeometry {
  // The Butterfly's ID dots at this distance from the key (mm); patlab's Butterfly / SSL
  // standard pattern has 65 (the paper gives no dimensions; the fit's sensitivity to it is the
  // main caveat). In (10, 200].
  double id_radius_mm = 65.0;
  double travel_mm = 2000.0;  // section II: 2 m across the view, centred on the camera axis
  double lateral_mm = 200.0;  // range of the runs' lateral offsets (uniform), (0, 2000]
  double correlation_length_mm = 100.0;   // of the correlated mechanism, (0, 1e4]
  double smoothing_sigma_samples = 10.0;  // the paper's estimate; 0: true errors (k = 1)
};
std::vector<OptionsProblem> Check(const NoiseFitGeometry& geometry);
void Validate(const NoiseFitGeometry& geometry);

enum class DatumKind { kPatchX, kPatchY, kPatternX, kPatternY, kPatternTheta };

struct FitDatum {
  std::string name;
  DatumKind kind = DatumKind::kPatchX;
  double observed = 0.0;      // the reported std (mm, rad)
  double se = 0.0;            // its sampling standard error (mm, rad), > 0
  double quantisation = 0.0;  // q_i: the pixel grid's std through the paper's estimate
  bool table1 = false;        // gets the between-size discrepancy delta
};

// Where the standard errors come from (the paper's n and the frames' autocorrelation).
struct PaperDataOptions {
  double table1_tau = 5.0;     // variance inflation of a single patch's std (Table I's chi-square
                               // intervals assume independent frames), >= 1
  double butterfly_tau = 2.0;  // the same for the Butterfly's stds, >= 1
  double butterfly_samples = 12850.0;  // 5 runs x ~2570 (section IV), > 5
  int butterfly_runs = 5;
};
std::vector<OptionsProblem> Check(const PaperDataOptions& options);
void Validate(const PaperDataOptions& options);

// Table I (6 rows) and the Butterfly (3 rows), with the quantisation of each subject measured by
// patlab track without noise or jitter (results/track_quantisation/table1.csv, est columns).
std::vector<FitDatum> PaperData(const PaperDataOptions& options);

// v_i = base_i + sum_j coefficient[i][j] m_j^2 (magnitudes in their name's units).
struct FitDesign {
  std::vector<FitDatum> data;
  std::vector<Magnitudes> coefficient;
  std::vector<double> base;  // q_i^2
  double k = 1.0;            // the smoothing estimate's factor
};
FitDesign BuildDesign(const std::vector<FitDatum>& data, const NoiseFitGeometry& geometry);
// Stage 1: delta from Table I alone (independent_x, independent_y and delta free: every
// size-independent mechanism acts on a single patch as those two do), and a copy of `design`
// with every Table I se replaced by sqrt(se^2 + delta^2).
FitDesign AddTable1Discrepancy(const FitDesign& design, double* delta_mm);
// sqrt(v_i) of every datum.
std::vector<double> Predict(const FitDesign& design, const Magnitudes& m);

struct NoiseFitOptions {
  std::array<bool, kNumMechanisms> free{};  // fitted; the others are held at `fixed`
  Magnitudes fixed{};                       // values of the held magnitudes
  Magnitudes upper{2.0, 2.0, 2.0, 10.0, 2000.0, 2.0, 2.0};  // search bounds, > 0
  bool fit_delta = false;   // fit delta (the Table I discrepancy) too; false: delta = 0
  int starts = 6;           // multistart points (deterministic from seed), [1, 100]
  int profile_points = 41;  // per profiled magnitude, [3, 1000]
  int bootstrap = 200;      // parametric bootstrap replicates, [0, 100000]
  uint64_t seed = 14;
};
std::vector<OptionsProblem> Check(const NoiseFitOptions& options);
void Validate(const NoiseFitOptions& options);

struct ProfilePoint {
  double value = 0.0;         // the profiled magnitude
  double minus2_log_l = 0.0;  // minimum over the others, minus the global minimum
};

enum class Identifiability {
  kFixed,        // not fitted
  kIdentified,   // finite interval not touching the upper search bound
  kUpperBound,   // interval [0, u] with u below the bound: only bounded from above
  kUnidentified  // the profile stays within 3.84 of the minimum up to the search bound
};
inline constexpr EnumNames<Identifiability, 4> kIdentifiabilityNames{{{
    {Identifiability::kFixed, "fixed"},
    {Identifiability::kIdentified, "identified"},
    {Identifiability::kUpperBound, "upper_bound"},
    {Identifiability::kUnidentified, "unidentified"},
}}};

struct MechanismEstimate {
  Mechanism mechanism = Mechanism::kIndependentX;
  bool free = false;
  double value = 0.0;
  double lower = 0.0, upper = 0.0;            // 95% profile likelihood interval
  double boot_lower = 0.0, boot_upper = 0.0;  // 2.5 / 97.5% bootstrap percentiles
  Identifiability verdict = Identifiability::kFixed;
  std::vector<ProfilePoint> profile;
  // The free magnitude whose bootstrap estimates correlate most with this one, and how much.
  int most_correlated = -1;
  double correlation = 0.0;
};

struct NoiseFitResult {
  Magnitudes best{};
  double delta = 0.0;
  double minus2_log_l = 0.0;
  double chi2 = 0.0;  // sum (d - pred)^2 / s^2 at the best fit
  int free_parameters = 0;
  std::vector<double> predicted;             // per datum
  std::vector<MechanismEstimate> estimates;  // one per mechanism, kMechanismNames order
  // Bootstrap correlation matrix of the free magnitudes (kNumMechanisms^2, row-major; NaN for
  // fixed ones or without bootstrap).
  std::vector<double> correlation;
};

// `step` (optional) is called after each unit of work: the fit, each profiled magnitude's
// interval and each bootstrap replicate (1 + free magnitudes + bootstrap steps in all, the last
// when bootstrap >= 2).
NoiseFitResult FitNoise(const FitDesign& design, const NoiseFitOptions& options,
                        const std::function<void()>& step = {});

// The blob-level check of the first-order model: the section-II track simulated frame by frame
// (runs x frames, 30 frames/s at 23 mm/s, per run a lateral offset and a heading from the seed),
// each mechanism drawn per patch and per frame, the camera roll and scale applied about the
// camera axis, the fast estimator on the Butterfly, each run's series through the paper's
// smoothing estimate (or about its mean when smoothing_sigma_samples is 0), pooled over runs.
// Quantisation is added in quadrature from `data` (as the model does). Returns per datum of
// `data` the simulated std.
std::vector<double> SimulateTrack(const std::vector<FitDatum>& data,
                                  const NoiseFitGeometry& geometry, const Magnitudes& m, int runs,
                                  int frames, uint64_t seed);

// The Butterfly model of the geometry: key at the origin, four ID dots at id_radius_mm in the
// directions of patterns/butterfly.toml.
estimate::Model ButterflyModel(double id_radius_mm);

}  // namespace patlab::paper

namespace patlab::paper {

// The whole camera-noise study behind `patlab fitnoise`: the fit of `free` (all mechanisms by
// default) with profiles and bootstrap, a table of nested candidate models (which mechanisms are
// needed), the sensitivity of a chosen model to the Butterfly's unknown size, and the blob-level
// check of the best fit. Returns the result files (name -> CSV text), written by the caller.
struct NoiseFitStudyOptions {
  NoiseFitGeometry geometry;
  PaperDataOptions paper;
  NoiseFitOptions fit;  // free: which mechanisms the main fit fits
  std::vector<double> sensitivity_radii_mm{45, 50, 55, 60, 65, 70, 80};
  int simulate_runs = 5;  // blob-level check (SimulateTrack), 0: none
  int simulate_frames = 2570;
  // Called as the study goes (steps done, steps in all): the main fit's steps (FitNoise), each
  // model's and each sensitivity fit, and the blob-level check; empty = no reports.
  std::function<void(int, int)> progress;
};
struct NoiseFitStudy {
  NoiseFitResult fit;
  std::vector<std::pair<std::string, std::string>> files;  // fit.csv, data.csv, profiles.csv,
                                                           // correlation.csv, models.csv,
                                                           // sensitivity.csv
  std::string summary;                                     // a few lines for people
};
NoiseFitStudy RunNoiseFitStudy(const NoiseFitStudyOptions& options);

}  // namespace patlab::paper

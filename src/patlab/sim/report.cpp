#include "patlab/sim/report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <span>

#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"

namespace patlab::sim {

namespace {

// A number cell: 10 significant digits, far below the Monte-Carlo error and identical on every
// run; NaN (no value) is an empty cell.
std::string Num(double v) { return std::isnan(v) ? "" : FormatSignificant(v, 10); }

std::string Int(int64_t v) { return std::to_string(v); }

// The x, y and theta error columns both CSVs share: mean, std and its 95% interval of each.
constexpr const char* kPoseErrorColumns[] = {
    "mean_x_mm",      "std_x_mm",      "std_x_lo_mm",      "std_x_hi_mm",
    "mean_y_mm",      "std_y_mm",      "std_y_lo_mm",      "std_y_hi_mm",
    "mean_theta_rad", "std_theta_rad", "std_theta_lo_rad", "std_theta_hi_rad"};

std::array<std::string, 12> PoseErrorFields(const AxisSummary& x, const AxisSummary& y,
                                            const AxisSummary& theta) {
  std::array<std::string, 12> fields;
  int k = 0;
  for (const AxisSummary* a : {&x, &y, &theta}) {
    fields[k++] = Num(a->mean);
    fields[k++] = Num(a->std);
    fields[k++] = Num(a->std_lower);
    fields[k++] = Num(a->std_upper);
  }
  return fields;
}

// Appends one CSV row: the head fields, the pose-error fields, the tail fields.
void AppendRow(std::span<const std::string> head, std::span<const std::string> middle,
               std::span<const std::string> tail, std::string* csv) {
  io::CsvWriter w(csv);
  for (std::span<const std::string> part : {head, middle, tail}) {
    for (const std::string& field : part) w.Cell(field);
  }
  w.EndRow();
}

// The header row: head columns, the pose-error columns, tail columns.
std::string Header(std::span<const char* const> head, std::span<const char* const> tail) {
  std::string csv;
  io::CsvWriter w(&csv);
  for (std::span<const char* const> part :
       {head, std::span<const char* const>(kPoseErrorColumns), tail}) {
    for (const char* column : part) w.Cell(column);
  }
  w.EndRow();
  return csv;
}

constexpr const char* kColumnsHead[] = {
    "pattern", "estimator", "sigma_mm", "trials", "noise",
};
constexpr const char* kColumnsTail[] = {"std_pos_mm",
                                        "std_pos_lo_mm",
                                        "std_pos_hi_mm",
                                        "rms_radial_mm",
                                        "mean_radial_mm",
                                        "std_radial_mm",
                                        "std_radial_lo_mm",
                                        "std_radial_hi_mm",
                                        "crlb_pos_mm",
                                        "crlb_theta_rad",
                                        "pred_pos_mm",
                                        "pred_theta_rad",
                                        "efficiency_pos",
                                        "efficiency_theta",
                                        "ml_nonconverged",
                                        "ml_first_nonconverged_trial",
                                        "ml_mean_iterations",
                                        "ks_x_d",
                                        "ks_x_p",
                                        "ks_y_d",
                                        "ks_y_p",
                                        "ks_theta_d",
                                        "ks_theta_p",
                                        "wilcoxon_pos_p",
                                        "wilcoxon_theta_p"};

}  // namespace

std::string ResultsCsv(const Experiment& experiment, const RunResult& result) {
  return Header(kColumnsHead, kColumnsTail) +
         ResultsCsvRows(experiment.noise.Describe(), result.points);
}

std::string ResultsCsvRows(const std::string& noise, std::span<const PointResult> points) {
  std::string csv;
  for (const PointResult& p : points) {
    for (const EstimatorResult& r : p.estimators) {
      // The iteration counters of the iterative estimators (ml, robust), in the ml_* columns.
      const bool ml =
          r.estimator == estimate::Estimator::kMl || r.estimator == estimate::Estimator::kRobust;
      const Comparison& c = r.vs_fast;
      const std::string head[] = {
          p.pattern,       std::string(estimate::EstimatorName(r.estimator)),
          Num(p.sigma_mm), Int(p.trials),
          noise,
      };
      const std::string tail[] = {Num(r.position_std_mm),
                                  Num(r.position_std_lower_mm),
                                  Num(r.position_std_upper_mm),
                                  Num(r.radial_rms_mm),
                                  Num(r.radial.mean),
                                  Num(r.radial.std),
                                  Num(r.radial.std_lower),
                                  Num(r.radial.std_upper),
                                  Num(r.crlb_position_mm),
                                  Num(r.crlb_theta_rad),
                                  Num(r.predicted_position_mm),
                                  Num(r.predicted_theta_rad),
                                  Num(Efficiency(r.crlb_position_mm, r.position_std_mm)),
                                  Num(Efficiency(r.crlb_theta_rad, r.theta.std)),
                                  ml ? Int(r.nonconverged) : "",
                                  ml ? Int(r.first_nonconverged_trial) : "",
                                  ml ? Num(r.mean_iterations) : "",
                                  c.computed ? Num(c.ks_x.d) : "",
                                  c.computed ? Num(c.ks_x.p_value) : "",
                                  c.computed ? Num(c.ks_y.d) : "",
                                  c.computed ? Num(c.ks_y.p_value) : "",
                                  c.computed ? Num(c.ks_theta.d) : "",
                                  c.computed ? Num(c.ks_theta.p_value) : "",
                                  c.computed ? Num(c.wilcoxon_position.p_value) : "",
                                  c.computed ? Num(c.wilcoxon_theta.p_value) : ""};
      AppendRow(head, PoseErrorFields(r.x, r.y, r.theta), tail, &csv);
    }
  }
  return csv;
}

namespace {

// The manifest fields both modes share: tool, inputs, grid, seed, field, noise.
nlohmann::json ManifestCommon(const Experiment& experiment) {
  using nlohmann::json;
  json j;
  j["tool"] = "patlab";
  j["version"] = PATLAB_VERSION;
  j["experiment"] = {{"file", experiment.source_file},
                     {"name", experiment.name},
                     {"description", experiment.description}};
  json patterns = json::array();
  for (size_t k = 0; k < experiment.patterns.size(); ++k) {
    patterns.push_back({{"name", experiment.patterns[k].name},
                        {"file", experiment.pattern_files[k]},
                        {"patches", experiment.patterns[k].size()}});
  }
  j["patterns"] = patterns;
  j["sigmas_mm"] = experiment.sigmas_mm;
  j["seed"] = experiment.seed;
  j["field_mm"] = {{"length", experiment.field_length_mm}, {"width", experiment.field_width_mm}};
  const NoiseModel& n = experiment.noise;
  j["noise"] = {{"model", n.Describe()},
                {"sigma_y_ratio", n.sigma_y_ratio},
                {"common_sigma_ratio", n.common_sigma_ratio},
                {"outlier_probability", n.outlier_probability},
                {"outlier_sigma_ratio", n.outlier_sigma_ratio}};
  return j;
}

// The manifest's last key, the files written (by name, without their folder), and its text.
std::string WithOutputs(nlohmann::json j, const std::vector<std::string>& outputs) {
  j["outputs"] = io::OutputNames(outputs);
  return j.dump(2) + "\n";
}

}  // namespace

std::string ManifestJson(const Experiment& experiment, const RunResult& result,
                         const std::vector<std::string>& outputs) {
  using nlohmann::json;
  json j = ManifestCommon(experiment);
  json estimators = json::array();
  for (auto e : experiment.estimators)
    estimators.push_back(std::string(estimate::EstimatorName(e)));
  j["estimators"] = estimators;
  j["trials_per_point"] = experiment.trials;
  // Bounded memory (runner.h): the block a point runs in, and the trials the KS and Wilcoxon
  // columns compare (the first block).
  j["statistics_block"] = {
      {"trials", kStatisticsBlockTrials},
      {"tests_on_first_trials", std::min(experiment.trials, kStatisticsBlockTrials)}};
  const estimate::Options& o = experiment.ml_options;
  j["ml_options"] = {{"max_iterations", o.max_iterations},
                     {"step_tolerance_mm", o.step_tolerance_mm},
                     {"step_tolerance_rad", o.step_tolerance_rad},
                     {"gradient_tolerance", o.gradient_tolerance}};
  int64_t nonconverged = 0;
  for (const PointResult& p : result.points) {
    for (const EstimatorResult& r : p.estimators) nonconverged += r.nonconverged;
  }
  j["ml_nonconverged_trials"] = nonconverged;
  j["total_trials"] = result.total_trials;
  return WithOutputs(std::move(j), outputs);
}

namespace {

constexpr const char* kDetectColumnsHead[] = {
    "pattern",
    "sigma_mm",
    "false_blob_rate_per_m2",
    "point",
    "frames",
    "robots",
    "noise",
    "detector_sigma_mm",
    "tolerance_mm2",
    "correct",
    "wrong_id",
    "unknown_id",
    "ambiguous",
    "missed",
    "false_positives",
    "detection_rate",
    "detection_rate_lo",
    "detection_rate_hi",
    "wrong_id_rate",
    "wrong_id_rate_lo",
    "wrong_id_rate_hi",
    "ambiguous_rate",
    "ambiguous_rate_lo",
    "ambiguous_rate_hi",
    "false_positives_per_frame",
    "false_positives_per_frame_lo",
    "false_positives_per_frame_hi",
};
constexpr const char* kDetectColumnsTail[] = {
    "crlb_pos_mm",     "crlb_theta_rad",  "false_blobs_per_frame",
    "missing_patches", "colour_errors",   "correspondences",
    "geometry_passed", "colour_rejected", "conflicts"};

}  // namespace

std::string DetectResultsCsv(const Experiment& experiment, const DetectRunResult& result) {
  return Header(kDetectColumnsHead, kDetectColumnsTail) +
         DetectResultsCsvRows(experiment.noise.Describe(), result.points);
}

std::string DetectResultsCsvRows(const std::string& noise,
                                 std::span<const DetectPointResult> points) {
  std::string csv;
  for (const DetectPointResult& p : points) {
    const std::string head[] = {
        p.pattern,
        Num(p.sigma_mm),
        Num(p.false_blob_rate_per_m2),
        Int(p.point),
        Int(p.frames),
        Int(p.robots),
        noise,
        Num(p.detector_sigma_mm),
        Num(p.tolerance_mm2),
        Int(p.correct),
        Int(p.wrong_id),
        Int(p.unknown_id),
        Int(p.ambiguous),
        Int(p.missed),
        Int(p.false_positives),
        Num(p.detection.rate),
        Num(p.detection.lower),
        Num(p.detection.upper),
        Num(p.wrong_id_rate.rate),
        Num(p.wrong_id_rate.lower),
        Num(p.wrong_id_rate.upper),
        Num(p.ambiguous_rate.rate),
        Num(p.ambiguous_rate.lower),
        Num(p.ambiguous_rate.upper),
        Num(p.false_positives_per_frame.rate),
        Num(p.false_positives_per_frame.lower),
        Num(p.false_positives_per_frame.upper),
    };
    const std::string tail[] = {
        Num(p.crlb_position_mm),
        Num(p.crlb_theta_rad),
        Num(static_cast<double>(p.false_blobs) / static_cast<double>(p.frames)),
        Int(p.missing_patches),
        Int(p.colour_errors),
        Int(p.stats.correspondences),
        Int(p.stats.geometry_passed),
        Int(p.stats.colour_rejected),
        Int(p.stats.conflicts)};
    AppendRow(head, PoseErrorFields(p.x, p.y, p.theta), tail, &csv);
  }
  return csv;
}

std::string DetectManifestJson(const Experiment& experiment, const DetectRunResult& result,
                               const std::vector<std::string>& outputs) {
  using nlohmann::json;
  json j = ManifestCommon(experiment);
  const DetectSettings& d = experiment.detect;
  const detect::DetectorOptions& o = d.detector.options;
  const SceneOptions& s = d.scene;
  j["correspondence"] = "detect";
  j["frames_per_point"] = d.frames;
  j["statistics_block"] = {{"frames", kStatisticsBlockFrames}};  // bounded memory (runner.h)
  j["false_blob_rates_per_m2"] = d.false_blob_rates_per_m2;
  j["detect"] = {{"settings", d.settings_file},
                 {"detector_sigma", std::string(NameOf(d.matched_sigma, kDetectorSigmaNames))},
                 {"match_radius_mm", d.match_radius_mm},
                 {"robots_per_team", s.robots_per_team},
                 {"missing_patch_probability", s.missing_patch_probability},
                 {"colour_error_probability", s.colour_error_probability},
                 {"false_blob_radius_mm", {s.false_blob_radius_min_mm, s.false_blob_radius_max_mm}},
                 {"ball", s.ball},
                 {"ball_colour", s.ball_colour},
                 {"robot_radius_mm", s.robot_radius_mm},
                 {"min_separation_mm", s.min_separation_mm}};
  j["detector"] = {{"patch_sigma_mm", o.patch_sigma_mm},
                   {"geometry_confidence", o.geometry_confidence},
                   {"reach_margin_mm", o.reach_margin_mm},
                   {"area_ratio", {o.area_ratio_min, o.area_ratio_max}},
                   {"missing_patch", std::string(detect::MissingPatchPolicyName(o.missing_patch))},
                   {"max_neighbours", o.max_neighbours},
                   {"estimator", std::string(estimate::EstimatorName(o.estimator))}};
  j["intervals"] = {{"rates", "Wilson score, 95%"},
                    {"false_positives_per_frame", "Garwood (exact Poisson), 95%"},
                    {"stds", "chi-square, 95%"}};
  j["total_frames"] = result.total_frames;
  return WithOutputs(std::move(j), outputs);
}

}  // namespace patlab::sim

#include "patlab/design/evaluate.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "patlab/core/format.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/sim/runner.h"

namespace patlab::design {

namespace {

namespace fs = std::filesystem;
using estimate::Estimator;

constexpr std::array<const char*, 2> kTeamColours = {"blue", "yellow"};
constexpr const char* kBallColour = "orange";
constexpr int kMaxRobotsPerTeam = 5;
constexpr int kDefaultIdColours = 2;

std::string NameOf(Estimator estimator) { return std::string(estimate::EstimatorName(estimator)); }

std::string CodebookFileFor(const std::string& pattern_file) {
  fs::path p(pattern_file);
  if (p.extension() != ".toml") return "";
  p.replace_extension(".codebook.toml");
  std::error_code ec;  // a name the file system refuses has no codebook
  return fs::is_regular_file(p, ec) ? p.string() : "";
}

// The palette of the frames: team colours, the codebook's colours, fixed-patch colours, the ball.
std::vector<std::string> FramePalette(const Pattern& pattern,
                                      const std::vector<std::string>& key_colours,
                                      const detect::Codebook& codebook) {
  std::vector<std::string> palette;
  const auto add = [&palette](const std::string& c) {
    if (std::find(palette.begin(), palette.end(), c) == palette.end()) palette.push_back(c);
  };
  for (const std::string& c : key_colours) add(c);
  for (const std::string& c : codebook.colours) add(c);
  for (const Patch& patch : pattern.patches) {
    if (patch.role == PatchRole::kFixed) add(patch.colour);
  }
  add(kBallColour);
  return palette;
}

// Part 4's experiment: whole frames of the pattern at every sigma, the detector told the true
// noise level (matched sigma).
//
// The detector's default max_neighbours (8) would reject every pattern of more than 9 patches
// (kMaxPatches is 12): part 4 derives it from the pattern, at least its non-key patches.
detect::DetectorOptions MisidentificationDetectorOptions(const Pattern& pattern) {
  detect::DetectorOptions options;
  options.max_neighbours = std::max(options.max_neighbours, pattern.size() - 1);
  return options;
}

sim::Experiment MisidentificationExperiment(const Pattern& pattern, const std::string& file,
                                            const EvaluateOptions& o,
                                            const std::vector<std::string>& key_colours,
                                            const detect::DetectorPattern& dp,
                                            int robots_per_team) {
  sim::Experiment e;
  e.name = "evaluate-" + pattern.name;
  e.correspondence = sim::Correspondence::kDetect;
  e.patterns = {pattern};
  e.pattern_files = {file};
  e.sigmas_mm = o.sigmas_mm;
  e.seed = o.seed;
  e.detect.detector = detect::MakeDetectorConfig(FramePalette(pattern, key_colours, dp.codebook),
                                                 MisidentificationDetectorOptions(pattern), {dp});
  e.detect.detector_pattern = {0};
  e.detect.frames = o.frames;
  e.detect.matched_sigma = true;
  e.detect.scene.field_length_mm = e.field_length_mm;
  e.detect.scene.field_width_mm = e.field_width_mm;
  e.detect.scene.robots_per_team = robots_per_team;
  return e;
}

Misidentification EvaluateMisidentification(const Pattern& pattern, const std::string& file,
                                            const EvaluateOptions& o) {
  Misidentification part;
  const std::string shipped = o.id_colours ? "" : CodebookFileFor(file);
  std::vector<std::string> id_colours;
  if (shipped.empty()) {
    id_colours.assign(kEvaluateIdColours.begin(),
                      kEvaluateIdColours.begin() + o.id_colours.value_or(kDefaultIdColours));
  }
  std::vector<std::string> key_colours(kTeamColours.begin(), kTeamColours.end());
  const Patch& key = pattern.patches[pattern.key_index];
  if (!key.colour.empty()) key_colours = {key.colour};

  const detect::DetectorPattern dp =
      formats::MakeDetectorPattern(pattern, key_colours, shipped, id_colours, o.tolerance_mm);
  part.codebook = shipped.empty() ? "generated" : shipped;
  part.id_colours = dp.codebook.colours;
  part.ids = static_cast<int>(dp.codebook.entries.size());
  if (part.ids == 0) {
    part.skipped_reason = "no IDs with " + std::to_string(part.id_colours.size()) +
                          (part.id_colours.size() == 1 ? " colour" : " colours") +
                          "; expected a larger --id-colors";
    return part;
  }
  const int robots_per_team = std::min(kMaxRobotsPerTeam, part.ids);
  part.robots_per_frame = robots_per_team * static_cast<int>(key_colours.size());
  const sim::Experiment e =
      MisidentificationExperiment(pattern, file, o, key_colours, dp, robots_per_team);
  Validate(e);
  sim::RunOptions run;
  run.threads = o.threads;
  if (o.progress) {
    run.progress = [&o](int done, int total) { o.progress(1 + done, 1 + total); };
  }
  part.result = sim::RunDetectExperiment(e, run);
  part.run = true;
  return part;
}

// Part 2: one known-correspondence point at sigma, every estimator.
sim::RunResult MonteCarlo(const Pattern& pattern, const std::string& file,
                          const EvaluateOptions& o) {
  sim::Experiment e;
  e.name = "evaluate-" + pattern.name;
  e.patterns = {pattern};
  e.pattern_files = {file};
  e.estimators.assign(estimate::kAllEstimators.begin(), estimate::kAllEstimators.end());
  e.sigmas_mm = {o.sigma_mm};
  e.trials = o.trials;
  e.seed = o.seed;
  Validate(e);
  sim::RunOptions run;
  run.threads = o.threads;
  const int units = 1 + static_cast<int>(o.sigmas_mm.size());
  if (o.progress) run.progress = [&o, units](int done, int) { o.progress(done, units); };
  return sim::RunExperiment(e, run);
}

}  // namespace

std::vector<OptionsProblem> Check(const EvaluateOptions& o) {
  OptionsChecker check;
  check.Require("--sigma", o.sigma_mm,
                std::isfinite(o.sigma_mm) && o.sigma_mm > 0.0 && o.sigma_mm <= 1e6,
                "a patch std in mm > 0");
  sim::CheckTrials(o.trials, "--trials", &check);
  if (o.id_colours) {
    check.IntegerInRange("--id-colors", *o.id_colours, 1,
                         static_cast<int64_t>(kEvaluateIdColours.size()));
  }
  sim::CheckFrames(o.frames, "--frames", &check);
  sim::CheckSigmas(o.sigmas_mm, "--sigmas", &check);
  check.Require("--threads", o.threads, o.threads >= 0 && o.threads <= sim::kMaxThreads,
                "0 (all cores) to " + std::to_string(sim::kMaxThreads));
  return check.Take();
}

void Validate(const EvaluateOptions& options) { ThrowFirstProblem(Check(options)); }

EvaluationReport EvaluatePattern(const Pattern& pattern, const std::string& file,
                                 const EvaluateOptions& options) {
  Validate(options);
  EvaluationReport r;
  r.options = options;
  r.pattern = pattern;
  r.file = file;

  // 1. Geometry.
  const estimate::Model model = estimate::Model::FromPattern(pattern);
  r.crlb = estimate::CramerRaoBound(model);
  for (Estimator est : estimate::kAllEstimators) {
    r.geometry.push_back({est, estimate::PredictedStd(model, est)});
  }
  // 2. Monte-Carlo with known correspondence.
  r.monte_carlo = MonteCarlo(pattern, file, options);
  // 3. ID capacity, as patlab ids.
  r.ids.symmetry = detect::FindSymmetry(pattern, options.tolerance_mm);
  for (int n : options.colour_counts) {
    r.ids.counts.emplace_back(n, detect::CountIds(pattern, r.ids.symmetry, n));
  }
  // 4. Misidentification in whole frames.
  r.misidentification = EvaluateMisidentification(pattern, file, options);
  return r;
}

// ---------------------------------------------------------------------------------------------
// Text.

namespace {

std::string Rate(const stats::Proportion& p) {
  return StringPrintf("%.4f [%.4f, %.4f]", p.rate, p.lower, p.upper);
}

std::string GeometryText(const EvaluationReport& r) {
  const estimate::StdPerSigma& crlb = r.crlb;
  std::string out =
      "\n1. Accuracy from geometry (first order, std per mm of patch sigma, isotropic Gaussian "
      "noise)\n"
      "   estimator  position mm/mm  CRLB     efficiency  angle mrad/mm  CRLB     efficiency\n";
  for (const GeometryRow& g : r.geometry) {
    out += StringPrintf(
        "   %-9s  %-14.4f  %-7.4f  %-10.3f  %-13.3f  %-7.3f  %.3f\n", NameOf(g.estimator).c_str(),
        g.predicted.position_per_axis, crlb.position_per_axis,
        sim::Efficiency(crlb.position_per_axis, g.predicted.position_per_axis),
        1e3 * g.predicted.theta, 1e3 * crlb.theta, sim::Efficiency(crlb.theta, g.predicted.theta));
  }
  return out;
}

std::string MonteCarloText(const EvaluationReport& r) {
  const sim::PointResult& point = r.monte_carlo.points.at(0);
  std::string out = "\n2. Accuracy by Monte-Carlo at sigma = " + FormatNumber(r.options.sigma_mm) +
                    " mm (" + std::to_string(point.trials) + " trials, random poses, seed " +
                    std::to_string(r.options.seed) + ")\n";
  out +=
      "   estimator  position std mm [95% CI]   predicted  angle std mrad [95% CI]    "
      "predicted\n";
  for (const sim::EstimatorResult& er : point.estimators) {
    const std::string position = StringPrintf("%.4f [%.4f, %.4f]", er.position_std_mm,
                                              er.position_std_lower_mm, er.position_std_upper_mm);
    const std::string angle = StringPrintf("%.3f [%.3f, %.3f]", 1e3 * er.theta.std,
                                           1e3 * er.theta.std_lower, 1e3 * er.theta.std_upper);
    out += StringPrintf("   %-9s  %-25s  %-9.4f  %-25s  %.3f", NameOf(er.estimator).c_str(),
                        position.c_str(), er.predicted_position_mm, angle.c_str(),
                        1e3 * er.predicted_theta_rad);
    if (er.nonconverged > 0) out += "  (" + std::to_string(er.nonconverged) + " not converged)";
    out += "\n";
  }
  out +=
      StringPrintf("   Cramer-Rao bound: position %.4f mm, angle %.3f mrad\n",
                   point.estimators[0].crlb_position_mm, 1e3 * point.estimators[0].crlb_theta_rad);
  return out;
}

std::string IdCapacityText(const EvaluationReport& r) {
  const int rotations = r.ids.symmetry.effective_order();
  std::string out = "\n3. ID capacity (paper Table II; symmetry tolerance " +
                    FormatNumber(r.options.tolerance_mm) + " mm)\n   " + std::to_string(rotations) +
                    (rotations == 1 ? " rotation about the key that geometry cannot tell apart: "
                                      "geometry fixes the rotation\n"
                                    : " rotations about the key that geometry cannot tell apart: "
                                      "colours decide\n");
  out += "   ID colours ";
  for (const auto& [n, ids] : r.ids.counts) out += StringPrintf("  %8d", n);
  out += "\n   IDs        ";
  for (const auto& [n, ids] : r.ids.counts) {
    out += StringPrintf("  %8llu", static_cast<unsigned long long>(ids));
  }
  out += "\n   " + detect::SymmetrySummary(r.ids.symmetry) + "\n";
  return out + detect::SymmetryTable(r.ids.symmetry, "   ");
}

std::string MisidentificationText(const EvaluationReport& r) {
  const Misidentification& m = r.misidentification;
  std::string colours;
  for (const std::string& c : m.id_colours) colours += (colours.empty() ? "" : ", ") + c;
  std::string out = "\n4. Misidentification in whole frames (" + std::to_string(m.ids) +
                    (m.ids == 1 ? " ID of " : " IDs of ") + colours +
                    (m.codebook == "generated" ? "" : " from " + m.codebook) + ")\n";
  if (!m.run) return out + "   not run: " + m.skipped_reason + "\n";
  out += "   " + std::to_string(r.options.frames) + " frames per sigma, " +
         std::to_string(m.robots_per_frame) + " robots per frame; detector patch_sigma_mm = max(" +
         FormatNumber(detect::DetectorOptions{}.patch_sigma_mm) + ", sigma)\n";
  out += "   sigma mm  detection [95%]           wrong ID [95%]            ambiguous [95%]\n";
  for (const sim::DetectPointResult& d : m.result.points) {
    out += StringPrintf("   %-8s  %-24s  %-24s  %s\n", FormatNumber(d.sigma_mm).c_str(),
                        Rate(d.detection).c_str(), Rate(d.wrong_id_rate).c_str(),
                        Rate(d.ambiguous_rate).c_str());
  }
  return out +
         "   detection: correct / robots; wrong ID: wrong / (correct + wrong);\n"
         "   ambiguous: rotation decided by neither geometry nor colours / robots\n";
}

}  // namespace

std::string EvaluationText(const EvaluationReport& r) {
  const size_t slots = detect::IdSlots(r.pattern).size();
  return "pattern " + r.pattern.name + " (" + r.file + "): " + std::to_string(r.pattern.size()) +
         " patches, " + std::to_string(slots) + (slots == 1 ? " ID slot\n" : " ID slots\n") +
         GeometryText(r) + MonteCarloText(r) + IdCapacityText(r) + MisidentificationText(r);
}

// ---------------------------------------------------------------------------------------------
// JSON.

namespace {

using nlohmann::json;

json ProportionJson(const stats::Proportion& p) {
  return {{"count", p.count},
          {"total", p.total},
          {"rate", p.rate},
          {"lower", p.lower},
          {"upper", p.upper}};
}

json GeometryJson(const EvaluationReport& r) {
  json geometry;
  geometry["crlb_position_mm_per_mm"] = r.crlb.position_per_axis;
  geometry["crlb_theta_rad_per_mm"] = r.crlb.theta;
  for (const GeometryRow& g : r.geometry) {
    geometry["estimators"].push_back(
        {{"estimator", NameOf(g.estimator)},
         {"predicted_position_mm_per_mm", g.predicted.position_per_axis},
         {"predicted_theta_rad_per_mm", g.predicted.theta},
         {"efficiency_position",
          sim::Efficiency(r.crlb.position_per_axis, g.predicted.position_per_axis)},
         {"efficiency_theta", sim::Efficiency(r.crlb.theta, g.predicted.theta)}});
  }
  return geometry;
}

json MonteCarloJson(const EvaluationReport& r) {
  const sim::PointResult& point = r.monte_carlo.points.at(0);
  json mc = {{"sigma_mm", r.options.sigma_mm}, {"trials", point.trials}, {"seed", r.options.seed}};
  for (const sim::EstimatorResult& er : point.estimators) {
    mc["estimators"].push_back(
        {{"estimator", NameOf(er.estimator)},
         {"std_position_mm", er.position_std_mm},
         {"std_position_lo_mm", er.position_std_lower_mm},
         {"std_position_hi_mm", er.position_std_upper_mm},
         {"std_theta_rad", er.theta.std},
         {"std_theta_lo_rad", er.theta.std_lower},
         {"std_theta_hi_rad", er.theta.std_upper},
         {"predicted_position_mm", er.predicted_position_mm},
         {"predicted_theta_rad", er.predicted_theta_rad},
         {"crlb_position_mm", er.crlb_position_mm},
         {"crlb_theta_rad", er.crlb_theta_rad},
         {"efficiency_position", sim::Efficiency(er.crlb_position_mm, er.position_std_mm)},
         {"efficiency_theta", sim::Efficiency(er.crlb_theta_rad, er.theta.std)},
         {"ml_nonconverged", er.nonconverged}});
  }
  return mc;
}

json IdCapacityJson(const EvaluationReport& r) {
  const detect::Symmetry& sym = r.ids.symmetry;
  json ids = {{"tolerance_mm", r.options.tolerance_mm},
              {"rotations", sym.effective_order()},
              {"accepted_shifts", sym.shifts},
              {"group_shifts", sym.group_shifts},
              {"effective_shifts", sym.effective_shifts},
              {"shift_fits", json::array()},
              {"counts", json::array()}};
  for (const detect::ShiftFit& fit : sym.fits) {
    ids["shift_fits"].push_back({{"shift", fit.shift},
                                 {"angle_rad", fit.angle_rad},
                                 {"residual_mm", fit.residual_mm},
                                 {"accepted", fit.accepted},
                                 {"in_group", fit.in_group},
                                 {"preserves_roles", fit.preserves_roles}});
  }
  for (const auto& [n, count] : r.ids.counts) {
    ids["counts"].push_back({{"colours", n}, {"ids", count}});
  }
  return ids;
}

json MisidentificationJson(const EvaluationReport& r) {
  const Misidentification& m = r.misidentification;
  json mis = {{"run", m.run},
              {"codebook", m.codebook},
              {"id_colours", m.id_colours},
              {"ids", m.ids},
              {"frames_per_sigma", r.options.frames},
              {"robots_per_frame", m.robots_per_frame},
              {"points", json::array()}};
  if (!m.run) mis["skipped_reason"] = m.skipped_reason;
  for (const sim::DetectPointResult& d : m.result.points) {
    mis["points"].push_back({{"sigma_mm", d.sigma_mm},
                             {"detector_sigma_mm", d.detector_sigma_mm},
                             {"robots", d.robots},
                             {"correct", d.correct},
                             {"wrong_id", d.wrong_id},
                             {"unknown_id", d.unknown_id},
                             {"ambiguous", d.ambiguous},
                             {"missed", d.missed},
                             {"false_positives", d.false_positives},
                             {"detection", ProportionJson(d.detection)},
                             {"wrong_id_rate", ProportionJson(d.wrong_id_rate)},
                             {"ambiguous_rate", ProportionJson(d.ambiguous_rate)}});
  }
  return mis;
}

json ReportJson(const EvaluationReport& r) {
  json j;
  j["pattern"] = r.pattern.name;
  j["file"] = r.file;
  j["patches"] = r.pattern.size();
  j["id_slots"] = detect::IdSlots(r.pattern).size();
  j["geometry"] = GeometryJson(r);
  j["monte_carlo"] = MonteCarloJson(r);
  j["ids"] = IdCapacityJson(r);
  j["misidentification"] = MisidentificationJson(r);
  return j;
}

}  // namespace

std::string EvaluationJson(const EvaluateOptions& options,
                           const std::vector<EvaluationReport>& reports) {
  json j;
  j["tool"] = "patlab evaluate";
  j["version"] = PATLAB_VERSION;
  j["seed"] = options.seed;
  j["patterns"] = json::array();
  for (const EvaluationReport& r : reports) j["patterns"].push_back(ReportJson(r));
  return j.dump(2) + "\n";
}

}  // namespace patlab::design

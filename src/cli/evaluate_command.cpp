// patlab evaluate: one report for a pattern designer. For each pattern: its accuracy from the
// geometry (first-order prediction, Cramer-Rao bound, efficiency), the same by Monte-Carlo at one
// patch sigma (the known-correspondence runner), its ID capacity (paper Table II), and how often
// the detector misidentifies it in whole simulated frames (the detect-mode runner).
//
// Each pattern is evaluated alone with two programmatically built experiments (sim::Experiment),
// both seeded from --seed: a pattern's report does not depend on the other patterns given, nor on
// --threads.
#include <algorithm>
#include <array>
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/text_output.h"
#include "patlab/core/error.h"
#include "patlab/detect/codebook.h"
#include "patlab/detect/settings.h"
#include "patlab/estimate/bounds.h"
#include "patlab/io/pattern_file.h"
#include "patlab/io/toml_util.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/runner.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;

constexpr const char* kExamples = R"(examples:
  patlab evaluate butterfly                          # the whole report, < 1 s on 2 cores
  patlab evaluate triangle patterns/my-pattern.toml --json > report.json
  patlab evaluate butterfly --sigma 0.8 --trials 1000000
  patlab evaluate ssl-standard --sigmas 3,3.5,4,4.5 --frames 5000
  patlab evaluate butterfly --id-colors 4 --colors 2,3,4,5

A PATTERN is a pattern file path or a name in --patterns-dir. The report has four parts:
 1. accuracy from the geometry: each estimator's first-order std per mm of patch sigma
    (position per axis, angle), the Cramer-Rao bound, efficiency = bound^2 / predicted^2;
 2. the same by Monte-Carlo at --sigma (isotropic Gaussian patch noise, random poses on the
    2800 x 2300 mm field): simulated std with its 95% chi-square interval beside the prediction;
 3. ID capacity as patlab ids computes it (--colors, --tolerance);
 4. misidentification: --frames whole frames per --sigmas value, each with up to 5 robots per
    team (blue, yellow keys) with distinct IDs and a ball, through the detector (default
    options, patch_sigma_mm matched to the noise: max(2, sigma)); the codebook is
    <pattern>.codebook.toml next to the pattern file if there is one and --id-colors is not
    given, else every ID of --id-colors colours (default 2). Rates with 95% Wilson intervals.
Output is the same for any --threads. Exit status: 0 ok, 2 bad input.
)";

// The ID colour names of generated codebooks, in order (--id-colors N takes the first N).
constexpr std::array<const char*, 8> kIdColourNames = {"pink", "green",  "cyan",  "white",
                                                       "red",  "purple", "brown", "grey"};
constexpr std::array<const char*, 2> kTeamColours = {"blue", "yellow"};
constexpr const char* kBallColour = "orange";
constexpr int kMaxRobotsPerTeam = 5;

struct EvaluateOptions {
  std::vector<std::string> patterns;
  double sigma_mm = 1.0;           // Monte-Carlo patch sigma (mm), > 0
  int64_t trials = 100000;         // Monte-Carlo trials, 2..1e9
  std::string colors = "2,3,4";    // ID capacity: palette sizes
  double tolerance_mm = 10.0;      // symmetry tolerance (mm), as patlab ids
  std::string sigmas = "1,2,3,4";  // misidentification: patch sigmas (mm)
  int id_colors = 2;  // misidentification codebook colours, 1..8, when given (id_colors_given);
                      // otherwise the shipped codebook if there is one, else 2
  bool id_colors_given = false;
  int64_t frames = 1000;  // misidentification frames per sigma, 1..1e8
  std::string seed = "1";
  int threads = 0;
  bool json = false;
  std::string patterns_dir = "patterns";
};

// Everything the flags say, checked in one place (docs/architecture.md rule 4).
struct Settings {
  std::vector<int> colour_counts;
  std::vector<double> sigmas_mm;
  uint64_t seed = 1;
};

Settings Validate(const EvaluateOptions& o) {
  if (o.patterns.empty()) {
    throw InputError(
        "missing PATTERN; expected 'patlab evaluate PATTERN... [options]' (see --help)");
  }
  if (!std::isfinite(o.sigma_mm) || !(o.sigma_mm > 0.0) || o.sigma_mm > 1e6) {
    throw InputError("--sigma is " + io::FormatNumber(o.sigma_mm) +
                     "; expected a patch std in mm > 0");
  }
  if (o.trials < 2 || o.trials > 1'000'000'000) {
    throw InputError("--trials is " + std::to_string(o.trials) +
                     "; expected an integer in 2..1000000000");
  }
  CheckTolerance(o.tolerance_mm);
  if (o.id_colors_given &&
      (o.id_colors < 1 || o.id_colors > static_cast<int>(kIdColourNames.size()))) {
    throw InputError("--id-colors is " + std::to_string(o.id_colors) +
                     "; expected an integer from 1 to 8");
  }
  if (o.frames < 1 || o.frames > 100'000'000) {
    throw InputError("--frames is " + std::to_string(o.frames) +
                     "; expected an integer in 1..100000000");
  }
  CheckThreads(o.threads);
  Settings s;
  s.colour_counts = ParseColourCounts(o.colors);
  const std::string sigmas_expected = "strictly increasing finite numbers >= 0 (mm), e.g. 1,2,3,4";
  s.sigmas_mm = ParseNumberList(o.sigmas, "--sigmas", sigmas_expected);
  for (size_t k = 0; k < s.sigmas_mm.size(); ++k) {
    const double v = s.sigmas_mm[k];
    if (!std::isfinite(v) || v < 0.0 || v > 1e6 || (k > 0 && !(v > s.sigmas_mm[k - 1]))) {
      throw InputError("--sigmas has " + io::FormatNumber(v) + "; expected " + sigmas_expected);
    }
  }
  s.seed = ParseSeed(o.seed, "--seed");
  return s;
}

// ---------------------------------------------------------------------------------------------
// The four parts of one pattern's report.

struct GeometryRow {
  estimate::Estimator estimator;
  estimate::StdPerSigma predicted;
};

struct IdsPart {
  detect::Symmetry symmetry;
  std::vector<std::pair<int, uint64_t>> counts;  // (colours, IDs)
};

struct MisidPart {
  bool run = false;
  std::string skipped_reason;           // when !run
  std::string codebook;                 // "generated" or the codebook file
  std::vector<std::string> id_colours;  // the codebook's colours
  int ids = 0;
  int robots_per_frame = 0;
  sim::DetectRunResult result;
};

struct Report {
  Pattern pattern;
  std::string file;
  estimate::StdPerSigma crlb;
  std::vector<GeometryRow> geometry;
  sim::RunResult monte_carlo;  // one point, every estimator
  IdsPart ids;
  MisidPart misid;
};

std::string CodebookFileFor(const std::string& pattern_file) {
  fs::path p(pattern_file);
  if (p.extension() != ".toml") return "";
  p.replace_extension(".codebook.toml");
  return fs::is_regular_file(p) ? p.string() : "";
}

MisidPart EvaluateMisidentification(const Pattern& pattern, const std::string& file,
                                    const EvaluateOptions& o, const Settings& s) {
  MisidPart part;
  const std::string shipped = o.id_colors_given ? "" : CodebookFileFor(file);
  std::vector<std::string> id_colours;
  if (shipped.empty()) {
    id_colours.assign(kIdColourNames.begin(), kIdColourNames.begin() + o.id_colors);
  }
  std::vector<std::string> key_colours(kTeamColours.begin(), kTeamColours.end());
  const Patch& key = pattern.patches[pattern.key_index];
  if (!key.colour.empty()) key_colours = {key.colour};

  detect::DetectorPattern dp =
      detect::MakeDetectorPattern(pattern, key_colours, shipped, id_colours, o.tolerance_mm);
  part.codebook = shipped.empty() ? "generated" : shipped;
  part.id_colours = dp.codebook.colours;
  part.ids = static_cast<int>(dp.codebook.entries.size());
  if (part.ids == 0) {
    part.skipped_reason = "no IDs with " + std::to_string(part.id_colours.size()) +
                          (part.id_colours.size() == 1 ? " colour" : " colours") +
                          "; expected a larger --id-colors";
    return part;
  }
  // The palette: team colours, the codebook's colours, fixed-patch colours, the ball.
  std::vector<std::string> palette;
  const auto add = [&palette](const std::string& c) {
    if (std::find(palette.begin(), palette.end(), c) == palette.end()) palette.push_back(c);
  };
  for (const std::string& c : key_colours) add(c);
  for (const std::string& c : dp.codebook.colours) add(c);
  for (const Patch& patch : pattern.patches) {
    if (patch.role == PatchRole::kFixed) add(patch.colour);
  }
  add(kBallColour);

  sim::Experiment e;
  e.name = "evaluate-" + pattern.name;
  e.correspondence = sim::Correspondence::kDetect;
  e.patterns = {pattern};
  e.pattern_files = {file};
  e.sigmas_mm = s.sigmas_mm;
  e.seed = s.seed;
  e.detect.detector = detect::MakeDetectorConfig(palette, detect::DetectorOptions{}, {dp});
  e.detect.detector_pattern = {0};
  e.detect.frames = o.frames;
  e.detect.matched_sigma = true;
  e.detect.scene.field_length_mm = e.field_length_mm;
  e.detect.scene.field_width_mm = e.field_width_mm;
  e.detect.scene.robots_per_team = std::min(kMaxRobotsPerTeam, part.ids);
  part.robots_per_frame = e.detect.scene.robots_per_team * static_cast<int>(key_colours.size());
  sim::RunOptions run;
  run.threads = o.threads;
  part.result = sim::RunDetectExperiment(e, run);
  part.run = true;
  return part;
}

Report EvaluatePattern(const std::string& reference, const EvaluateOptions& o, const Settings& s) {
  Report r;
  r.file = io::ResolvePatternPath(reference, o.patterns_dir);
  r.pattern = io::LoadPatternFile(r.file);

  // 1. Geometry.
  const estimate::Model model = estimate::Model::FromPattern(r.pattern);
  r.crlb = estimate::CramerRaoBound(model);
  for (estimate::Estimator est : estimate::kAllEstimators) {
    r.geometry.push_back({est, estimate::PredictedStd(model, est)});
  }

  // 2. Monte-Carlo with known correspondence: one data point, every estimator.
  sim::Experiment e;
  e.name = "evaluate-" + r.pattern.name;
  e.patterns = {r.pattern};
  e.pattern_files = {r.file};
  e.estimators.assign(estimate::kAllEstimators.begin(), estimate::kAllEstimators.end());
  e.sigmas_mm = {o.sigma_mm};
  e.trials = o.trials;
  e.seed = s.seed;
  sim::RunOptions run;
  run.threads = o.threads;
  r.monte_carlo = sim::RunExperiment(e, run);

  // 3. ID capacity, as patlab ids.
  r.ids.symmetry = detect::FindSymmetry(r.pattern, o.tolerance_mm);
  for (int n : s.colour_counts) {
    r.ids.counts.emplace_back(n, detect::CountIds(r.pattern, r.ids.symmetry, n));
  }

  // 4. Misidentification in whole frames.
  r.misid = EvaluateMisidentification(r.pattern, r.file, o, s);
  return r;
}

// ---------------------------------------------------------------------------------------------
// Output.

std::string Format(const char* format, auto... values) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

std::string NameOf(estimate::Estimator est) { return std::string(estimate::EstimatorName(est)); }

double Efficiency(double bound, double achieved) {
  return achieved > 0.0 ? (bound * bound) / (achieved * achieved) : std::nan("");
}

std::string Rate(const stats::Proportion& p) {
  return Format("%.4f [%.4f, %.4f]", p.rate, p.lower, p.upper);
}

void PrintText(const Report& r, const EvaluateOptions& o, const Settings& s, std::ostream& out) {
  const Pattern& p = r.pattern;
  const size_t slots = detect::IdSlots(p).size();
  out << "pattern " << p.name << " (" << r.file << "): " << p.size() << " patches, " << slots
      << (slots == 1 ? " ID slot\n" : " ID slots\n");

  out << "\n1. Accuracy from geometry (first order, std per mm of patch sigma, isotropic "
         "Gaussian noise)\n";
  out << "   estimator  position mm/mm  CRLB     efficiency  angle mrad/mm  CRLB     efficiency\n";
  for (const GeometryRow& g : r.geometry) {
    out << Format(
        "   %-9s  %-14.4f  %-7.4f  %-10.3f  %-13.3f  %-7.3f  %.3f\n", NameOf(g.estimator).c_str(),
        g.predicted.position_per_axis, r.crlb.position_per_axis,
        Efficiency(r.crlb.position_per_axis, g.predicted.position_per_axis),
        1e3 * g.predicted.theta, 1e3 * r.crlb.theta, Efficiency(r.crlb.theta, g.predicted.theta));
  }

  const sim::PointResult& point = r.monte_carlo.points.at(0);
  out << "\n2. Accuracy by Monte-Carlo at sigma = " << io::FormatNumber(o.sigma_mm) << " mm ("
      << point.trials << " trials, random poses, seed " << s.seed << ")\n";
  out << "   estimator  position std mm [95% CI]   predicted  angle std mrad [95% CI]    "
         "predicted\n";
  for (const sim::EstimatorResult& er : point.estimators) {
    const std::string position = Format("%.4f [%.4f, %.4f]", er.position_std_mm,
                                        er.position_std_lower_mm, er.position_std_upper_mm);
    const std::string angle = Format("%.3f [%.3f, %.3f]", 1e3 * er.theta.std,
                                     1e3 * er.theta.std_lower, 1e3 * er.theta.std_upper);
    out << Format("   %-9s  %-25s  %-9.4f  %-25s  %.3f", NameOf(er.estimator).c_str(),
                  position.c_str(), er.predicted_position_mm, angle.c_str(),
                  1e3 * er.predicted_theta_rad);
    if (er.nonconverged > 0) out << "  (" << er.nonconverged << " not converged)";
    out << "\n";
  }
  out << Format("   Cramer-Rao bound: position %.4f mm, angle %.3f mrad\n",
                point.estimators[0].crlb_position_mm, 1e3 * point.estimators[0].crlb_theta_rad);

  const int rotations = r.ids.symmetry.effective_order();
  out << "\n3. ID capacity (paper Table II; symmetry tolerance " << io::FormatNumber(o.tolerance_mm)
      << " mm)\n";
  out << "   " << rotations
      << (rotations == 1
              ? " rotation about the key that geometry cannot tell apart: geometry fixes "
                "the rotation\n"
              : " rotations about the key that geometry cannot tell apart: colours "
                "decide\n");
  out << "   ID colours ";
  for (const auto& [n, ids] : r.ids.counts) out << Format("  %8d", n);
  out << "\n   IDs        ";
  for (const auto& [n, ids] : r.ids.counts)
    out << Format("  %8llu", static_cast<unsigned long long>(ids));
  out << "\n";

  const MisidPart& m = r.misid;
  std::string colours;
  for (const std::string& c : m.id_colours) colours += (colours.empty() ? "" : ", ") + c;
  out << "\n4. Misidentification in whole frames (" << m.ids
      << (m.ids == 1 ? " ID of " : " IDs of ") << colours
      << (m.codebook == "generated" ? "" : " from " + m.codebook) << ")\n";
  if (!m.run) {
    out << "   not run: " << m.skipped_reason << "\n";
    return;
  }
  out << "   " << o.frames << " frames per sigma, " << m.robots_per_frame
      << " robots per frame; detector patch_sigma_mm = max("
      << io::FormatNumber(detect::DetectorOptions{}.patch_sigma_mm) << ", sigma)\n";
  out << "   sigma mm  detection [95%]           wrong ID [95%]            ambiguous [95%]\n";
  for (const sim::DetectPointResult& d : m.result.points) {
    out << Format("   %-8s  %-24s  %-24s  %s\n", io::FormatNumber(d.sigma_mm).c_str(),
                  Rate(d.detection).c_str(), Rate(d.wrong_id_rate).c_str(),
                  Rate(d.ambiguous_rate).c_str());
  }
  out << "   detection: correct / robots; wrong ID: wrong / (correct + wrong);\n"
         "   ambiguous: rotation decided by neither geometry nor colours / robots\n";
}

nlohmann::json ProportionJson(const stats::Proportion& p) {
  return {{"count", p.count},
          {"total", p.total},
          {"rate", p.rate},
          {"lower", p.lower},
          {"upper", p.upper}};
}

nlohmann::json ReportJson(const Report& r, const EvaluateOptions& o, const Settings& s) {
  nlohmann::json j;
  j["pattern"] = r.pattern.name;
  j["file"] = r.file;
  j["patches"] = r.pattern.size();
  j["id_slots"] = detect::IdSlots(r.pattern).size();

  nlohmann::json geometry;
  geometry["crlb_position_mm_per_mm"] = r.crlb.position_per_axis;
  geometry["crlb_theta_rad_per_mm"] = r.crlb.theta;
  for (const GeometryRow& g : r.geometry) {
    geometry["estimators"].push_back(
        {{"estimator", NameOf(g.estimator)},
         {"predicted_position_mm_per_mm", g.predicted.position_per_axis},
         {"predicted_theta_rad_per_mm", g.predicted.theta},
         {"efficiency_position",
          Efficiency(r.crlb.position_per_axis, g.predicted.position_per_axis)},
         {"efficiency_theta", Efficiency(r.crlb.theta, g.predicted.theta)}});
  }
  j["geometry"] = geometry;

  const sim::PointResult& point = r.monte_carlo.points.at(0);
  nlohmann::json mc = {{"sigma_mm", o.sigma_mm}, {"trials", point.trials}, {"seed", s.seed}};
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
         {"efficiency_position", Efficiency(er.crlb_position_mm, er.position_std_mm)},
         {"efficiency_theta", Efficiency(er.crlb_theta_rad, er.theta.std)},
         {"ml_nonconverged", er.nonconverged}});
  }
  j["monte_carlo"] = mc;

  nlohmann::json ids = {{"tolerance_mm", o.tolerance_mm},
                        {"rotations", r.ids.symmetry.effective_order()},
                        {"counts", nlohmann::json::array()}};
  for (const auto& [n, count] : r.ids.counts)
    ids["counts"].push_back({{"colours", n}, {"ids", count}});
  j["ids"] = ids;

  const MisidPart& m = r.misid;
  nlohmann::json mis = {{"run", m.run},
                        {"codebook", m.codebook},
                        {"id_colours", m.id_colours},
                        {"ids", m.ids},
                        {"frames_per_sigma", o.frames},
                        {"robots_per_frame", m.robots_per_frame},
                        {"points", nlohmann::json::array()}};
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
  j["misidentification"] = mis;
  return j;
}

int RunEvaluate(const std::vector<std::string>& args) {
  EvaluateOptions o;
  po::options_description visible("usage: patlab evaluate PATTERN... [options]\n\noptions");
  visible.add_options()("sigma", po::value(&o.sigma_mm)->default_value(o.sigma_mm),
                        "Monte-Carlo patch std (mm) of part 2")(
      "trials", po::value(&o.trials)->default_value(o.trials), "Monte-Carlo trials of part 2")(
      "colors,c", po::value(&o.colors)->default_value(o.colors),
      "ID palette sizes for the ID capacity of part 3, comma-separated")(
      "tolerance", po::value(&o.tolerance_mm)->default_value(o.tolerance_mm),
      "symmetry tolerance (mm) of parts 3 and 4 (paper section III: 10 mm)")(
      "sigmas", po::value(&o.sigmas)->default_value(o.sigmas),
      "patch stds (mm) of the misidentification frames of part 4")(
      "id-colors", po::value(&o.id_colors),
      "ID colours of part 4's codebook, 1..8 (default: <pattern>.codebook.toml next to the "
      "pattern file if present, else 2)")("frames", po::value(&o.frames)->default_value(o.frames),
                                          "frames per sigma of part 4")(
      "seed", po::value(&o.seed)->default_value(o.seed), "seed (integer >= 0)")(
      "threads", po::value(&o.threads)->default_value(o.threads),
      "worker threads (0 = all cores); the output does not depend on it")(
      "json", po::bool_switch(&o.json), "print one JSON object instead of text")(
      "patterns-dir", po::value(&o.patterns_dir)->default_value(o.patterns_dir),
      "where pattern names are looked up")("help,h", "show this help");
  po::variables_map vm;
  if (!ParseArguments(args, visible, "pattern", po::value(&o.patterns), -1, kExamples, &vm)) {
    return kExitOk;
  }
  o.id_colors_given = vm.count("id-colors") > 0;
  const Settings s = Validate(o);
  // Resolve every pattern before the first (long) run, so a typo fails at once.
  for (const std::string& reference : o.patterns) {
    io::LoadPatternFile(io::ResolvePatternPath(reference, o.patterns_dir));
  }
  std::vector<Report> reports;
  for (const std::string& reference : o.patterns)
    reports.push_back(EvaluatePattern(reference, o, s));

  if (o.json) {
    nlohmann::json j;
    j["tool"] = "patlab evaluate";
    j["version"] = PATLAB_VERSION;
    j["seed"] = s.seed;
    j["patterns"] = nlohmann::json::array();
    for (const Report& r : reports) j["patterns"].push_back(ReportJson(r, o, s));
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::ostringstream out;
  for (size_t k = 0; k < reports.size(); ++k) {
    if (k > 0) out << "\n";
    PrintText(reports[k], o, s, out);
  }
  std::cout << TrimLineEnds(out.str());
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND(
    "evaluate", "one report per pattern: accuracy vs the CRLB, ID capacity, misidentification",
    RunEvaluate);

}  // namespace patlab::cli

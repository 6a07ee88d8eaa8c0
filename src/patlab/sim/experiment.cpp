#include "patlab/sim/experiment.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "patlab/detect/settings.h"
#include "patlab/io/pattern_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::sim {

namespace {

namespace fs = std::filesystem;
using io::FormatNumber;
using io::TomlReader;

void ReadNoiseTable(const TomlReader& r, NoiseModel* noise) {
  r.CheckKeys({"sigma_y_ratio", "common_sigma_ratio", "outlier_probability",
               "outlier_sigma_ratio"});
  noise->sigma_y_ratio = r.OptionalNumber("sigma_y_ratio").value_or(noise->sigma_y_ratio);
  noise->common_sigma_ratio =
      r.OptionalNumber("common_sigma_ratio").value_or(noise->common_sigma_ratio);
  noise->outlier_probability =
      r.OptionalNumber("outlier_probability").value_or(noise->outlier_probability);
  noise->outlier_sigma_ratio =
      r.OptionalNumber("outlier_sigma_ratio").value_or(noise->outlier_sigma_ratio);
  if (!(noise->sigma_y_ratio > 0.0)) {
    r.Fail("sigma_y_ratio", r.Describe("sigma_y_ratio") + " is " +
                                FormatNumber(noise->sigma_y_ratio) + "; expected a number > 0");
  }
  if (!(noise->common_sigma_ratio >= 0.0)) {
    r.Fail("common_sigma_ratio", r.Describe("common_sigma_ratio") + " is " +
                                     FormatNumber(noise->common_sigma_ratio) +
                                     "; expected a number >= 0");
  }
  if (!(noise->outlier_probability >= 0.0 && noise->outlier_probability < 1.0)) {
    r.Fail("outlier_probability", r.Describe("outlier_probability") + " is " +
                                      FormatNumber(noise->outlier_probability) +
                                      "; expected a probability in [0, 1)");
  }
  if (!(noise->outlier_sigma_ratio > 0.0)) {
    r.Fail("outlier_sigma_ratio", r.Describe("outlier_sigma_ratio") + " is " +
                                      FormatNumber(noise->outlier_sigma_ratio) +
                                      "; expected a number > 0");
  }
}

std::vector<double> ReadSigmaGrid(const TomlReader& r) {
  r.CheckKeys({"values", "from", "to", "steps"});
  std::vector<double> sigmas;
  if (r.Has("values")) {
    if (r.Has("from") || r.Has("to") || r.Has("steps")) {
      r.Fail("values", "[sigma] has both values and from/to/steps; expected one of the two forms");
    }
    const toml::node& node = *r.table().get("values");
    const toml::array* values = node.as_array();
    if (values == nullptr || values->empty()) {
      r.Fail("values", "values in [sigma] is " +
                           (values == nullptr ? io::TypeName(node) : std::string("empty")) +
                           "; expected a non-empty array of numbers (mm)");
    }
    for (const toml::node& v : *values) {
      double value;
      if (const auto* i = v.as_integer()) {
        value = static_cast<double>(i->get());
      } else if (const auto* f = v.as_floating_point()) {
        value = f->get();
      } else {
        r.Fail("values", "values in [sigma] contains " + io::TypeName(v) +
                             "; expected numbers (mm)");
      }
      sigmas.push_back(value);
    }
  } else {
    const double from = r.Number("from");
    const double to = r.Number("to");
    const auto steps = r.OptionalInteger("steps");
    if (!steps) r.Fail("steps", "missing steps in [sigma]; expected an integer >= 2");
    if (*steps < 2 || *steps > 10000) {
      r.Fail("steps", "steps in [sigma] is " + std::to_string(*steps) +
                          "; expected an integer in 2..10000");
    }
    if (!(to > from)) {
      r.Fail("to", "to in [sigma] is " + FormatNumber(to) + "; expected a number > from (" +
                       FormatNumber(from) + ")");
    }
    for (int64_t k = 0; k < *steps; ++k) {
      sigmas.push_back(from + (to - from) * static_cast<double>(k) / static_cast<double>(*steps - 1));
    }
  }
  for (size_t k = 0; k < sigmas.size(); ++k) {
    const double s = sigmas[k];
    if (!std::isfinite(s) || s < 0.0) {
      r.Fail("values", "sigma " + FormatNumber(s) + " in [sigma]; expected finite numbers >= 0 (mm)");
    }
    if (k > 0 && !(s > sigmas[k - 1])) {
      r.Fail("values", "sigma values in [sigma] are not increasing at " + FormatNumber(s) +
                           "; expected strictly increasing values");
    }
  }
  return sigmas;
}

const toml::table& SubTable(const TomlReader& r, std::string_view key) {
  const toml::node* node = r.table().get(key);
  if (node->as_table() == nullptr) {
    r.Fail(key, std::string(key) + " is " + io::TypeName(*node) + "; expected a table [" +
                    std::string(key) + "]");
  }
  return *node->as_table();
}

// The [detect] table, after [field]: see DetectSettings. Every scene option is validated by
// ValidateSceneOptions (the one place), its message placed at the key's line.
void ReadDetectTable(const TomlReader& d, const fs::path& base, double field_length_mm,
                     double field_width_mm, DetectSettings* s) {
  d.CheckKeys({"settings", "frames", "robots_per_team", "false_blob_rate_per_m2",
               "false_blob_radius_min_mm", "false_blob_radius_max_mm", "missing_patch_probability",
               "colour_error_probability", "ball", "ball_colour", "robot_radius_mm",
               "min_separation_mm", "match_radius_mm", "detector_sigma"});
  if (!d.Has("settings")) {
    d.Fail("settings",
           "missing settings in [detect]; expected a detector settings file (relative to the "
           "experiment)");
  }
  const std::string settings = d.String("settings");
  s->settings_file = (base / settings).lexically_normal().string();
  if (!fs::is_regular_file(s->settings_file)) {
    d.Fail("settings", "settings in [detect] is \"" + settings + "\", but " + s->settings_file +
                           " is not a file; expected a detector settings file (relative to the "
                           "experiment)");
  }
  s->detector = detect::LoadDetectorSettings(s->settings_file);

  if (const auto frames = d.OptionalInteger("frames")) {
    if (*frames < 1 || *frames > 100'000'000) {
      d.Fail("frames", d.Describe("frames") + " is " + std::to_string(*frames) +
                           "; expected an integer in 1..100000000");
    }
    s->frames = *frames;
  }
  SceneOptions& o = s->scene;
  o.field_length_mm = field_length_mm;
  o.field_width_mm = field_width_mm;
  if (const auto robots = d.OptionalInteger("robots_per_team")) {
    if (*robots < 1 || *robots > 1000) {
      d.Fail("robots_per_team", d.Describe("robots_per_team") + " is " + std::to_string(*robots) +
                                    "; expected an integer in 1..1000");
    }
    o.robots_per_team = static_cast<int>(*robots);
  }
  for (auto [key, field] : {std::pair{"false_blob_radius_min_mm", &o.false_blob_radius_min_mm},
                            std::pair{"false_blob_radius_max_mm", &o.false_blob_radius_max_mm},
                            std::pair{"missing_patch_probability", &o.missing_patch_probability},
                            std::pair{"colour_error_probability", &o.colour_error_probability},
                            std::pair{"robot_radius_mm", &o.robot_radius_mm},
                            std::pair{"min_separation_mm", &o.min_separation_mm}}) {
    *field = d.OptionalNumber(key).value_or(*field);
  }
  o.ball = d.OptionalBool("ball").value_or(o.ball);
  o.ball_colour = d.OptionalString("ball_colour").value_or(o.ball_colour);
  s->match_radius_mm = d.OptionalNumber("match_radius_mm").value_or(s->match_radius_mm);
  if (!(s->match_radius_mm > 0.0)) {
    d.Fail("match_radius_mm", d.Describe("match_radius_mm") + " is " +
                                  FormatNumber(s->match_radius_mm) +
                                  "; expected a number > 0 (mm)");
  }
  if (const auto mode = d.OptionalString("detector_sigma")) {
    if (*mode != "settings" && *mode != "matched") {
      d.Fail("detector_sigma", d.Describe("detector_sigma") + " is \"" + *mode +
                                   "\"; expected \"settings\" or \"matched\"");
    }
    s->matched_sigma = *mode == "matched";
  }

  // false_blob_rate_per_m2: one number, or an array of them (a second grid axis).
  s->false_blob_rates_per_m2 = {0.0};
  if (d.Has("false_blob_rate_per_m2")) {
    const toml::node& node = *d.table().get("false_blob_rate_per_m2");
    std::vector<const toml::node*> items;
    if (const toml::array* values = node.as_array()) {
      if (values->empty()) {
        d.Fail("false_blob_rate_per_m2", d.Describe("false_blob_rate_per_m2") +
                                             " is empty; expected a number or an array of numbers");
      }
      for (const toml::node& v : *values) items.push_back(&v);
    } else {
      items.push_back(&node);
    }
    s->false_blob_rates_per_m2.clear();
    for (const toml::node* v : items) {
      double value;
      if (const auto* i = v->as_integer()) {
        value = static_cast<double>(i->get());
      } else if (const auto* f = v->as_floating_point()) {
        value = f->get();
      } else {
        throw InputError(io::LocOf(d.file(), *v), d.Describe("false_blob_rate_per_m2") + " is " +
                                                      io::TypeName(*v) +
                                                      "; expected a number or an array of numbers");
      }
      if (!s->false_blob_rates_per_m2.empty() && !(value > s->false_blob_rates_per_m2.back())) {
        throw InputError(io::LocOf(d.file(), *v),
                         d.Describe("false_blob_rate_per_m2") + " is not increasing at " +
                             FormatNumber(value) + "; expected strictly increasing values");
      }
      o.false_blob_rate_per_m2 = value;
      if (auto problem = ValidateSceneOptions(o);
          problem && problem->field == "false_blob_rate_per_m2") {
        throw InputError(
            io::LocOf(d.file(), *v),
            d.Describe("false_blob_rate_per_m2") + problem->message.substr(problem->field.size()));
      }
      s->false_blob_rates_per_m2.push_back(value);
    }
  }
  o.false_blob_rate_per_m2 = s->false_blob_rates_per_m2.front();
  if (auto problem = ValidateSceneOptions(o)) {
    // The field is checked with [field]; every other scene option is a [detect] key.
    d.Fail(problem->field,
           d.Describe(problem->field) + problem->message.substr(problem->field.size()));
  }
  if (o.ball && std::find(s->detector.palette.begin(), s->detector.palette.end(), o.ball_colour) ==
                    s->detector.palette.end()) {
    std::string palette;
    for (const std::string& c : s->detector.palette) palette += (palette.empty() ? "" : ", ") + c;
    d.Fail("ball_colour", d.Describe("ball_colour") + " is \"" + o.ball_colour +
                              "\"; expected a colour of the detector palette (" + palette +
                              ") or ball = false");
  }
}

// Resolves the detect-mode `patterns` (names of the settings' [[pattern]]s) and checks that
// every pattern's scene can be drawn (enough IDs, room on the field).
void ResolveDetectPatterns(const TomlReader& r, const TomlReader& d, const toml::array& patterns,
                           uint64_t seed, Experiment* e) {
  DetectSettings& s = e->detect;
  for (const toml::node& item : patterns) {
    const std::string& name = item.as_string()->get();
    int index = -1;
    std::string names;
    for (size_t k = 0; k < s.detector.patterns.size(); ++k) {
      const std::string& candidate = s.detector.patterns[k].pattern.name;
      if (candidate == name) index = static_cast<int>(k);
      names += (names.empty() ? "" : ", ") + candidate;
    }
    if (index < 0) {
      throw InputError(io::LocOf(r.file(), item),
                       "pattern '" + name + "' is not in the detector settings " + s.settings_file +
                           "; expected one of: " + names);
    }
    for (const Pattern& seen : e->patterns) {
      if (seen.name == name) {
        throw InputError(io::LocOf(r.file(), item),
                         "pattern '" + name + "' is listed twice; expected each pattern once");
      }
    }
    const detect::DetectorPattern& dp = s.detector.patterns[index];
    const int ids = static_cast<int>(dp.codebook.entries.size());
    if (s.scene.robots_per_team > ids) {
      d.Fail("robots_per_team",
             d.Describe("robots_per_team") + " is " + std::to_string(s.scene.robots_per_team) +
                 "; expected at most " + std::to_string(ids) + " (the IDs of " + name + ")");
    }
    // One trial scene: the robots and the ball must fit on the field.
    detect::DetectorConfig config = s.detector;
    config.patterns = {dp};
    const detect::Detector detector(std::move(config));
    SceneOptions scene = s.scene;
    scene.pattern = 0;
    RandomStream rng(seed, 0, 0);
    try {
      GenerateScene(detector, scene, PatchNoise{}, rng);
    } catch (const InputError& error) {
      const std::string what = error.what();
      d.Fail("robots_per_team", d.Describe("robots_per_team") + " is " +
                                    std::to_string(s.scene.robots_per_team) + " (" + name +
                                    "): " + (what.starts_with("scene: ") ? what.substr(7) : what));
    }
    e->patterns.push_back(dp.pattern);
    e->pattern_files.push_back(s.settings_file);
    s.detector_pattern.push_back(index);
  }
}

}  // namespace

Experiment LoadExperimentFile(const std::string& path) {
  const toml::table root = io::ParseTomlFile(path);
  TomlReader r(root, path);
  const auto corr = r.OptionalString("correspondence");
  const bool detect_mode = corr && *corr == "detect";
  if (!detect_mode) {
    r.CheckKeys({"name", "description", "patterns", "patterns_dir", "estimators", "trials", "seed",
                 "correspondence", "sigma", "field", "noise", "noise_file", "ml"});
  } else {
    for (auto [key, instead] :
         {std::pair{"trials", "frames in [detect]"},
          std::pair{"estimators", "estimator in the detector settings' [detector] table"},
          std::pair{"ml", "ml_max_iterations in the detector settings' [detector] table"},
          std::pair{"patterns_dir", "patterns_dir in the detector settings"}}) {
      if (r.Has(key)) {
        r.Fail(key, std::string(key) + " is not used with correspondence = \"detect\"; expected " +
                        instead);
      }
    }
    r.CheckKeys({"name", "description", "patterns", "seed", "correspondence", "sigma", "field",
                 "noise", "noise_file", "detect"});
  }
  Experiment e;
  e.source_file = path;
  e.name = r.String("name");
  e.description = r.OptionalString("description").value_or("");
  const fs::path base = fs::path(path).parent_path();
  const std::string patterns_dir =
      (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal().string();

  if (corr && *corr != "known" && *corr != "detect") {
    r.Fail("correspondence",
           "correspondence is \"" + *corr + "\"; expected \"known\" or \"detect\"");
  }
  if (detect_mode) e.correspondence = Correspondence::kDetect;

  // patterns = ["simple", "path/to/file.toml", ...]
  const toml::node* patterns_node = root.get("patterns");
  if (patterns_node == nullptr) r.Fail("patterns", "missing patterns; expected an array of pattern names or files");
  const toml::array* patterns = patterns_node->as_array();
  if (patterns == nullptr || patterns->empty()) {
    r.Fail("patterns", "patterns is " +
                           (patterns == nullptr ? io::TypeName(*patterns_node) : std::string("empty")) +
                           "; expected a non-empty array of pattern names or files");
  }
  for (const toml::node& item : *patterns) {
    const auto* name = item.as_string();
    if (name == nullptr) {
      r.Fail("patterns", "patterns contains " + io::TypeName(item) +
                             "; expected pattern names or files (strings)");
    }
    if (detect_mode) continue;  // names of the detector settings' patterns: after [detect]
    std::string reference = name->get();
    // A reference with a path separator or .toml is a file relative to the experiment file.
    if (reference.find('/') != std::string::npos || reference.ends_with(".toml")) {
      reference = (base / reference).lexically_normal().string();
    }
    std::string file;
    try {
      file = io::ResolvePatternPath(reference, patterns_dir);
    } catch (const InputError& error) {
      throw InputError(io::LocOf(path, item), error.what());
    }
    Pattern pattern = io::LoadPatternFile(file);
    for (const Pattern& seen : e.patterns) {
      if (seen.name == pattern.name) {
        throw InputError(io::LocOf(path, item), "pattern '" + pattern.name +
                                                    "' is listed twice; expected each pattern once");
      }
    }
    e.patterns.push_back(std::move(pattern));
    e.pattern_files.push_back(file);
  }

  // estimators = ["fast", "ml"]
  if (const toml::node* est_node = root.get("estimators")) {
    const toml::array* ests = est_node->as_array();
    if (ests == nullptr || ests->empty()) {
      r.Fail("estimators", "estimators is " +
                               (ests == nullptr ? io::TypeName(*est_node) : std::string("empty")) +
                               "; expected a non-empty array of \"fast\", \"ml\", \"lsq\", \"key\"");
    }
    for (const toml::node& item : *ests) {
      const auto* name = item.as_string();
      estimate::Estimator est;
      if (name == nullptr || !estimate::ParseEstimator(name->get(), &est)) {
        throw InputError(io::LocOf(path, item),
                         "unknown estimator " +
                             (name == nullptr ? io::TypeName(item) : "\"" + name->get() + "\"") +
                             "; expected \"fast\", \"ml\", \"lsq\" or \"key\"");
      }
      for (estimate::Estimator seen : e.estimators) {
        if (seen == est) {
          throw InputError(io::LocOf(path, item), "estimator \"" + name->get() +
                                                      "\" is listed twice; expected each once");
        }
      }
      e.estimators.push_back(est);
    }
  } else {
    e.estimators = {estimate::Estimator::kFast, estimate::Estimator::kMl};
  }

  if (const auto trials = r.OptionalInteger("trials")) {
    if (*trials < 2 || *trials > 1'000'000'000) {
      r.Fail("trials", "trials is " + std::to_string(*trials) +
                           "; expected an integer in 2..1000000000");
    }
    e.trials = *trials;
  }
  if (const auto seed = r.OptionalInteger("seed")) {
    if (*seed < 0) r.Fail("seed", "seed is " + std::to_string(*seed) + "; expected an integer >= 0");
    e.seed = static_cast<uint64_t>(*seed);
  }

  if (!r.Has("sigma")) r.Fail("sigma", "missing [sigma]; expected a table with values = [...] or from, to, steps");
  e.sigmas_mm = ReadSigmaGrid(TomlReader(SubTable(r, "sigma"), path, "[sigma]"));

  if (r.Has("field")) {
    TomlReader f(SubTable(r, "field"), path, "[field]");
    f.CheckKeys({"length_mm", "width_mm"});
    e.field_length_mm = f.OptionalNumber("length_mm").value_or(e.field_length_mm);
    e.field_width_mm = f.OptionalNumber("width_mm").value_or(e.field_width_mm);
    for (const char* key : {"length_mm", "width_mm"}) {
      const double v = f.OptionalNumber(key).value_or(1.0);
      if (!(v >= 0.0)) f.Fail(key, f.Describe(key) + " is " + FormatNumber(v) + "; expected a number >= 0 (mm)");
      if (detect_mode && !(v > 0.0)) {
        f.Fail(key, f.Describe(key) + " is " + FormatNumber(v) +
                        "; expected a number > 0 (mm) with correspondence = \"detect\"");
      }
    }
  }

  if (r.Has("noise") && r.Has("noise_file")) {
    r.Fail("noise_file", "both [noise] and noise_file are given; expected one of the two");
  }
  if (r.Has("noise")) {
    ReadNoiseTable(TomlReader(SubTable(r, "noise"), path, "[noise]"), &e.noise);
  } else if (const auto noise_file = r.OptionalString("noise_file")) {
    const std::string noise_path = (base / *noise_file).lexically_normal().string();
    const toml::table noise_root = io::ParseTomlFile(noise_path);
    ReadNoiseTable(TomlReader(noise_root, noise_path), &e.noise);
  }

  if (detect_mode) {
    if (!r.Has("detect")) {
      r.Fail("detect",
             "missing [detect] with correspondence = \"detect\"; expected a table "
             "with at least settings = \"<detector settings file>\"");
    }
    const TomlReader d(SubTable(r, "detect"), path, "[detect]");
    ReadDetectTable(d, base, e.field_length_mm, e.field_width_mm, &e.detect);
    ResolveDetectPatterns(r, d, *patterns, e.seed, &e);
  }

  if (r.Has("ml")) {
    TomlReader m(SubTable(r, "ml"), path, "[ml]");
    m.CheckKeys({"max_iterations", "step_tolerance_mm", "step_tolerance_rad", "gradient_tolerance"});
    estimate::Options& o = e.ml_options;
    if (const auto it = m.OptionalInteger("max_iterations")) {
      if (*it < 1 || *it > 1000) {
        m.Fail("max_iterations", m.Describe("max_iterations") + " is " + std::to_string(*it) +
                                     "; expected an integer in 1..1000");
      }
      o.max_iterations = static_cast<int>(*it);
    }
    for (auto [key, field] : {std::pair{"step_tolerance_mm", &o.step_tolerance_mm},
                              std::pair{"step_tolerance_rad", &o.step_tolerance_rad},
                              std::pair{"gradient_tolerance", &o.gradient_tolerance}}) {
      *field = m.OptionalNumber(key).value_or(*field);
      if (!(*field >= 0.0)) {
        m.Fail(key, m.Describe(key) + " is " + FormatNumber(*field) + "; expected a number >= 0");
      }
    }
  }
  return e;
}

void ApplyOverrides(const Overrides& overrides, Experiment* experiment) {
  if (overrides.trials != 0 && experiment->correspondence == Correspondence::kDetect) {
    if (overrides.trials < 1 || overrides.trials > 100'000'000) {
      throw InputError("--trials is " + std::to_string(overrides.trials) +
                       "; expected an integer in 1..100000000 (frames per point in detect mode)");
    }
    experiment->detect.frames = overrides.trials;
  } else if (overrides.trials != 0) {
    if (overrides.trials < 2 || overrides.trials > 1'000'000'000) {
      throw InputError("--trials is " + std::to_string(overrides.trials) +
                       "; expected an integer in 2..1000000000");
    }
    experiment->trials = overrides.trials;
  }
  if (overrides.has_seed) experiment->seed = overrides.seed;
  if (!overrides.sigmas_mm.empty()) {
    for (size_t k = 0; k < overrides.sigmas_mm.size(); ++k) {
      const double s = overrides.sigmas_mm[k];
      if (!std::isfinite(s) || s < 0.0 || (k > 0 && !(s > overrides.sigmas_mm[k - 1]))) {
        throw InputError("--sigmas has " + FormatNumber(s) +
                         "; expected strictly increasing finite numbers >= 0 (mm)");
      }
    }
    experiment->sigmas_mm = overrides.sigmas_mm;
  }
}

}  // namespace patlab::sim

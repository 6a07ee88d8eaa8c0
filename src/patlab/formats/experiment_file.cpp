// Experiment files: the TOML tables of an experiment, read one concept at a time. Types and
// structure are checked as they are read (io::TomlReader); every limit comes from the options'
// Check functions (experiment.h, noise.h, scene.h, estimate::Check), their first problem placed
// at the line of its key.
#include "patlab/formats/experiment_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>

#include "patlab/core/format.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::sim {

namespace {

namespace fs = std::filesystem;
using io::TomlReader;

// Throws the first problem at the line of its key in `r`, the field renamed as `r` describes it
// ("max_iterations" -> "max_iterations in [ml]").
void FailAtFirst(const TomlReader& r, const std::vector<OptionsProblem>& problems) {
  if (problems.empty()) return;
  const OptionsProblem& p = problems.front();
  const bool named = p.message.starts_with(p.field);
  r.Fail(p.field, named ? r.Describe(p.field) + p.message.substr(p.field.size()) : p.message);
}

// The value of a number node (integer or float), or nullopt for any other type.
std::optional<double> NumberOf(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

// The non-empty array at `key` (present): "<key> is empty; expected <expected>" otherwise.
const toml::array& NonEmptyArray(const TomlReader& r, std::string_view key,
                                 const std::string& expected) {
  const toml::node& node = *r.table().get(key);
  const toml::array* values = node.as_array();
  if (values == nullptr || values->empty()) {
    r.Fail(key, r.Describe(key) + " is " +
                    (values == nullptr ? io::TypeName(node) : std::string("empty")) +
                    "; expected " + expected);
  }
  return *values;
}

const toml::table& SubTable(const TomlReader& r, std::string_view key) {
  const toml::node* node = r.table().get(key);
  if (node->as_table() == nullptr) {
    r.Fail(key, std::string(key) + " is " + io::TypeName(*node) + "; expected a table [" +
                    std::string(key) + "]");
  }
  return *node->as_table();
}

// ---------------------------------------------------------------------------------------------
// Top level.

// The keys each mode knows; detect mode names where the known-mode keys went instead.
void CheckTopLevelKeys(const TomlReader& r, bool detect_mode) {
  if (!detect_mode) {
    r.CheckKeys({"name", "description", "patterns", "patterns_dir", "estimators", "trials", "seed",
                 "correspondence", "sigma", "field", "noise", "noise_file", "ml"});
    return;
  }
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

Correspondence ReadCorrespondence(const TomlReader& r) {
  const auto name = r.OptionalString("correspondence");
  if (!name) return Correspondence::kKnown;
  const auto value = FindName(*name, kCorrespondenceNames);
  if (!value) {
    r.Fail("correspondence",
           "correspondence is \"" + *name + "\"; expected " + NameList(kCorrespondenceNames));
  }
  return *value;
}

// patterns = ["simple", "path/to/file.toml", ...]: strings, checked before any is resolved.
const toml::array& ReadPatternList(const TomlReader& r) {
  if (!r.Has("patterns")) {
    r.Fail("patterns", "missing patterns; expected an array of pattern names or files");
  }
  const toml::array& patterns =
      NonEmptyArray(r, "patterns", "a non-empty array of pattern names or files");
  for (const toml::node& item : patterns) {
    if (item.as_string() == nullptr) {
      r.Fail("patterns", "patterns contains " + io::TypeName(item) +
                             "; expected pattern names or files (strings)");
    }
  }
  return patterns;
}

// A pattern may appear once: its name is the key of its rows in the results.
void CheckNotListed(const std::vector<Pattern>& seen, const std::string& name, const FileLoc& loc) {
  for (const Pattern& pattern : seen) {
    if (pattern.name == name) {
      throw InputError(loc, "pattern '" + name + "' is listed twice; expected each pattern once");
    }
  }
}

// Known mode: pattern names resolve in patterns_dir; a reference with a path separator or .toml
// is a file relative to the experiment file.
void LoadKnownPatterns(const TomlReader& r, const toml::array& patterns, const fs::path& base,
                       Experiment* e) {
  const std::string patterns_dir =
      (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal().string();
  for (const toml::node& item : patterns) {
    std::string reference = item.as_string()->get();
    if (reference.find('/') != std::string::npos || reference.ends_with(".toml")) {
      reference = (base / reference).lexically_normal().string();
    }
    std::string file;
    try {
      file = io::ResolvePatternPath(reference, patterns_dir);
    } catch (const InputError& error) {
      throw InputError(io::LocOf(r.file(), item), error.what());
    }
    Pattern pattern = io::LoadPatternFile(file);
    CheckNotListed(e->patterns, pattern.name, io::LocOf(r.file(), item));
    e->patterns.push_back(std::move(pattern));
    e->pattern_files.push_back(file);
  }
}

// estimators = ["fast", "ml"] (default: fast and ml).
std::vector<estimate::Estimator> ReadEstimators(const TomlReader& r) {
  if (!r.Has("estimators")) return {estimate::Estimator::kFast, estimate::Estimator::kMl};
  const std::string names = "\"fast\", \"ml\", \"lsq\", \"key\" or \"robust\"";
  std::vector<estimate::Estimator> estimators;
  for (const toml::node& item : NonEmptyArray(r, "estimators", "a non-empty array of " + names)) {
    const auto* name = item.as_string();
    estimate::Estimator estimator;
    if (name == nullptr || !estimate::ParseEstimator(name->get(), &estimator)) {
      throw InputError(io::LocOf(r.file(), item),
                       "unknown estimator " +
                           (name == nullptr ? io::TypeName(item) : "\"" + name->get() + "\"") +
                           "; expected " + names);
    }
    if (std::find(estimators.begin(), estimators.end(), estimator) != estimators.end()) {
      throw InputError(io::LocOf(r.file(), item),
                       "estimator \"" + name->get() + "\" is listed twice; expected each once");
    }
    estimators.push_back(estimator);
  }
  return estimators;
}

void ReadTrialsAndSeed(const TomlReader& r, Experiment* e) {
  if (const auto trials = r.OptionalInteger("trials")) {
    OptionsChecker check;
    CheckTrials(*trials, "trials", &check);
    FailAtFirst(r, check.problems());
    e->trials = *trials;
  }
  if (const auto seed = r.OptionalInteger("seed")) {
    OptionsChecker check;
    check.Require("seed", static_cast<double>(*seed), *seed >= 0, "an integer >= 0");
    FailAtFirst(r, check.problems());
    e->seed = static_cast<uint64_t>(*seed);
  }
}

// ---------------------------------------------------------------------------------------------
// [sigma], [field], [noise], [ml].

// [sigma]: values = [...], or from, to, steps (an evenly spaced grid, both ends included).
std::vector<double> ReadSigmaGrid(const TomlReader& r) {
  r.CheckKeys({"values", "from", "to", "steps"});
  std::vector<double> sigmas;
  OptionsChecker check;
  if (r.Has("values")) {
    if (r.Has("from") || r.Has("to") || r.Has("steps")) {
      r.Fail("values", "[sigma] has both values and from/to/steps; expected one of the two forms");
    }
    for (const toml::node& v : NonEmptyArray(r, "values", "a non-empty array of numbers (mm)")) {
      const auto value = NumberOf(v);
      if (!value) {
        r.Fail("values",
               r.Describe("values") + " contains " + io::TypeName(v) + "; expected numbers (mm)");
      }
      sigmas.push_back(*value);
    }
    CheckSigmas(sigmas, "values", &check);
  } else {
    const double from = r.Number("from");
    const double to = r.Number("to");
    const auto steps = r.OptionalInteger("steps");
    if (!steps) r.Fail("steps", "missing " + r.Describe("steps") + "; expected an integer >= 2");
    check.IntegerInRange("steps", *steps, 2, 10000)
        .NonNegative("from", from, "mm")
        .Require("to", to, to > from, "a number > from (" + FormatNumber(from) + ")");
    for (int64_t k = 0; k < *steps && check.problems().empty(); ++k) {
      sigmas.push_back(from +
                       (to - from) * static_cast<double>(k) / static_cast<double>(*steps - 1));
    }
  }
  FailAtFirst(r, check.problems());
  return sigmas;
}

// [field]: the area random poses (and detect-mode scenes) cover. Scenes need a field of some
// size; their limit (Check(SceneOptions)) is checked here, at the key's line.
void ReadField(const TomlReader& f, bool detect_mode, Experiment* e) {
  f.CheckKeys({"length_mm", "width_mm"});
  e->field_length_mm = f.OptionalNumber("length_mm").value_or(e->field_length_mm);
  e->field_width_mm = f.OptionalNumber("width_mm").value_or(e->field_width_mm);
  OptionsChecker check;
  CheckFieldSides(e->field_length_mm, e->field_width_mm, "length_mm", "width_mm", &check);
  if (detect_mode && check.problems().empty()) {
    SceneOptions scene;
    scene.field_length_mm = e->field_length_mm;
    scene.field_width_mm = e->field_width_mm;
    for (const OptionsProblem& p : Check(scene)) {
      if (p.field.starts_with("field_")) {
        const std::string key = p.field.substr(6);
        check.Fail(key,
                   key + p.message.substr(p.field.size()) + " with correspondence = \"detect\"");
      }
    }
  }
  FailAtFirst(f, check.problems());
}

NoiseModel ReadNoiseTable(const TomlReader& r) {
  r.CheckKeys({"sigma_y_ratio", "common_sigma_ratio", "outlier_probability", "outlier_sigma_ratio",
               "rotation_jitter_rad", "scale_jitter_ppm", "correlation_length_mm", "key_shift_x_mm",
               "id_shift_x_mm"});
  NoiseModel noise;
  for (auto [key, field] : {std::pair{"sigma_y_ratio", &noise.sigma_y_ratio},
                            std::pair{"common_sigma_ratio", &noise.common_sigma_ratio},
                            std::pair{"outlier_probability", &noise.outlier_probability},
                            std::pair{"outlier_sigma_ratio", &noise.outlier_sigma_ratio},
                            std::pair{"rotation_jitter_rad", &noise.rotation_jitter_rad},
                            std::pair{"scale_jitter_ppm", &noise.scale_jitter_ppm},
                            std::pair{"correlation_length_mm", &noise.correlation_length_mm},
                            std::pair{"key_shift_x_mm", &noise.key_shift_x_mm},
                            std::pair{"id_shift_x_mm", &noise.id_shift_x_mm}}) {
    *field = r.OptionalNumber(key).value_or(*field);
  }
  FailAtFirst(r, Check(noise));
  return noise;
}

// [noise], or noise_file (relative to the experiment), or the paper's isotropic Gaussian.
NoiseModel ReadNoise(const TomlReader& r, const fs::path& base) {
  if (r.Has("noise") && r.Has("noise_file")) {
    r.Fail("noise_file", "both [noise] and noise_file are given; expected one of the two");
  }
  if (r.Has("noise")) return ReadNoiseTable(TomlReader(SubTable(r, "noise"), r.file(), "[noise]"));
  if (const auto noise_file = r.OptionalString("noise_file")) {
    const std::string noise_path = (base / *noise_file).lexically_normal().string();
    std::error_code ec;
    if (fs::is_directory(noise_path, ec)) {
      r.Fail("noise_file", "noise_file \"" + EscapeForMessage(*noise_file) + "\" is a directory (" +
                               EscapeForMessage(noise_path) + "); expected a noise TOML file");
    }
    if (!fs::exists(noise_path, ec)) {
      r.Fail("noise_file", "noise_file \"" + EscapeForMessage(*noise_file) + "\" not found (" +
                               EscapeForMessage(noise_path) + "); expected a noise TOML file");
    }
    const toml::table noise_root = io::ParseTomlFile(noise_path);
    return ReadNoiseTable(TomlReader(noise_root, noise_path));
  }
  return NoiseModel{};
}

estimate::Options ReadMlTable(const TomlReader& m) {
  m.CheckKeys({"max_iterations", "step_tolerance_mm", "step_tolerance_rad", "gradient_tolerance"});
  estimate::Options o;
  if (const auto iterations = m.OptionalInteger("max_iterations")) {
    // A value beyond int's range is beyond the checked range too (the message shows int's limit).
    o.max_iterations = static_cast<int>(std::clamp<int64_t>(*iterations, INT32_MIN, INT32_MAX));
  }
  for (auto [key, field] : {std::pair{"step_tolerance_mm", &o.step_tolerance_mm},
                            std::pair{"step_tolerance_rad", &o.step_tolerance_rad},
                            std::pair{"gradient_tolerance", &o.gradient_tolerance}}) {
    *field = m.OptionalNumber(key).value_or(*field);
  }
  FailAtFirst(m, estimate::Check(o));
  return o;
}

// ---------------------------------------------------------------------------------------------
// [detect]: see DetectSettings.

// settings = "<file>", relative to the experiment; loaded (and checked) as a detector settings
// file.
void ReadDetectorSettings(const TomlReader& d, const fs::path& base, DetectSettings* s) {
  const std::string expected = "expected a detector settings file (relative to the experiment)";
  if (!d.Has("settings")) d.Fail("settings", "missing " + d.Describe("settings") + "; " + expected);
  const std::string settings = d.String("settings");
  s->settings_file = (base / settings).lexically_normal().string();
  std::error_code ec;  // a name the file system refuses is not a file
  if (!fs::is_regular_file(s->settings_file, ec)) {
    d.Fail("settings", d.Describe("settings") + " is \"" + settings + "\", but " +
                           s->settings_file + " is not a file; " + expected);
  }
  s->detector = detect::LoadDetectorSettings(s->settings_file);
}

// The scalar keys: frames, the scene's numbers and switches, match_radius_mm, detector_sigma.
void ReadDetectScalars(const TomlReader& d, DetectSettings* s) {
  s->frames = d.OptionalInteger("frames").value_or(s->frames);
  SceneOptions& o = s->scene;
  if (const auto robots = d.OptionalInteger("robots_per_team")) {
    o.robots_per_team = static_cast<int>(std::clamp<int64_t>(*robots, INT32_MIN, INT32_MAX));
  }
  for (auto [key, field] : {std::pair{"false_blob_radius_min_mm", &o.false_blob_radius_min_mm},
                            std::pair{"false_blob_radius_max_mm", &o.false_blob_radius_max_mm},
                            std::pair{"missing_patch_probability", &o.missing_patch_probability},
                            std::pair{"colour_error_probability", &o.colour_error_probability},
                            std::pair{"robot_radius_mm", &o.robot_radius_mm},
                            std::pair{"min_separation_mm", &o.min_separation_mm},
                            std::pair{"match_radius_mm", &s->match_radius_mm}}) {
    *field = d.OptionalNumber(key).value_or(*field);
  }
  o.ball = d.OptionalBool("ball").value_or(o.ball);
  o.ball_colour = d.OptionalString("ball_colour").value_or(o.ball_colour);
  if (const auto mode = d.OptionalString("detector_sigma")) {
    const auto matched = FindName(*mode, kDetectorSigmaNames);
    if (!matched) {
      d.Fail("detector_sigma", d.Describe("detector_sigma") + " is \"" + *mode + "\"; expected " +
                                   NameList(kDetectorSigmaNames));
    }
    s->matched_sigma = *matched;
  }
}

// false_blob_rate_per_m2: one number, or an array of them (a second grid axis), each checked
// at its own line.
void ReadFalseBlobRates(const TomlReader& d, DetectSettings* s) {
  s->false_blob_rates_per_m2 = {0.0};
  if (!d.Has("false_blob_rate_per_m2")) return;
  const std::string key = "false_blob_rate_per_m2";
  const std::string expected = "; expected a number or an array of numbers";
  const toml::node& node = *d.table().get(key);
  std::vector<const toml::node*> items;
  if (const toml::array* values = node.as_array()) {
    if (values->empty()) d.Fail(key, d.Describe(key) + " is empty" + expected);
    for (const toml::node& v : *values) items.push_back(&v);
  } else {
    items.push_back(&node);
  }
  s->false_blob_rates_per_m2.clear();
  SceneOptions scene = s->scene;
  for (const toml::node* v : items) {
    const FileLoc loc = io::LocOf(d.file(), *v);
    const auto value = NumberOf(*v);
    if (!value) throw InputError(loc, d.Describe(key) + " is " + io::TypeName(*v) + expected);
    if (!s->false_blob_rates_per_m2.empty() && !(*value > s->false_blob_rates_per_m2.back())) {
      throw InputError(loc, d.Describe(key) + " is not increasing at " + FormatNumber(*value) +
                                "; expected strictly increasing values");
    }
    scene.false_blob_rate_per_m2 = *value;
    for (const OptionsProblem& p : Check(scene)) {
      if (p.field == key) throw InputError(loc, d.Describe(key) + p.message.substr(key.size()));
    }
    s->false_blob_rates_per_m2.push_back(*value);
  }
}

// The ball must have a colour the detector knows, or the scene could not label it.
void CheckBallColour(const TomlReader& d, const DetectSettings& s) {
  const std::vector<std::string>& palette = s.detector.palette;
  if (!s.scene.ball ||
      std::find(palette.begin(), palette.end(), s.scene.ball_colour) != palette.end()) {
    return;
  }
  std::string names;
  for (const std::string& c : palette) names += (names.empty() ? "" : ", ") + c;
  d.Fail("ball_colour", d.Describe("ball_colour") + " is \"" + s.scene.ball_colour +
                            "\"; expected a colour of the detector palette (" + names +
                            ") or ball = false");
}

// The [detect] table, after [field] (the scene stands on the experiment's field).
void ReadDetectTable(const TomlReader& d, const fs::path& base, const Experiment& e,
                     DetectSettings* s) {
  d.CheckKeys({"settings", "frames", "robots_per_team", "false_blob_rate_per_m2",
               "false_blob_radius_min_mm", "false_blob_radius_max_mm", "missing_patch_probability",
               "colour_error_probability", "ball", "ball_colour", "robot_radius_mm",
               "min_separation_mm", "match_radius_mm", "detector_sigma"});
  ReadDetectorSettings(d, base, s);
  s->scene.field_length_mm = e.field_length_mm;
  s->scene.field_width_mm = e.field_width_mm;
  ReadDetectScalars(d, s);
  ReadFalseBlobRates(d, s);
  s->scene.false_blob_rate_per_m2 = s->false_blob_rates_per_m2.front();
  FailAtFirst(d, Check(*s));
  CheckBallColour(d, *s);
}

// The index of the settings' [[pattern]] called `name`; -1 and the list of names otherwise.
int FindDetectorPattern(const detect::DetectorConfig& config, const std::string& name,
                        std::string* names) {
  int index = -1;
  for (size_t k = 0; k < config.patterns.size(); ++k) {
    const std::string& candidate = config.patterns[k].pattern.name;
    if (candidate == name) index = static_cast<int>(k);
    *names += (names->empty() ? "" : ", ") + candidate;
  }
  return index;
}

// Robots and the ball are placed by rejection sampling (scene.cpp PlaceFree, 10000 attempts).
// While the exclusion disks of the objects already placed cover at most kMaxExcludedFraction of
// the region the next centre is drawn from, each attempt succeeds with probability >= 0.2, so a
// placement fails with probability <= 0.8^10000 < 1e-969: checked here at load time, the
// experiment's validity does not depend on the random draw (docs/hardening.md).
constexpr double kMaxExcludedFraction = 0.8;

// The larger of the robots' and the ball's excluded fractions for the last one placed.
double ExcludedFraction(const SceneOptions& o, int robots) {
  const double l = o.field_length_mm, w = o.field_width_mm, r = o.robot_radius_mm;
  const double robot_region = (l - 2 * r) * (w - 2 * r);
  const double robot_excluded =
      (robots - 1) * std::numbers::pi * o.min_separation_mm * o.min_separation_mm;
  double fraction = robot_excluded > 0 ? robot_excluded / robot_region : 0.0;
  if (o.ball) {
    const double rb = o.ball_radius_mm;
    const double ball_region = (l - 2 * rb) * (w - 2 * rb);
    fraction = std::max(fraction, robots * std::numbers::pi * (r + rb) * (r + rb) / ball_region);
  }
  return fraction;
}

// One trial scene of the pattern: enough IDs for robots_per_team, room for robots and ball.
void CheckSceneFits(const TomlReader& d, const DetectSettings& s, int index, uint64_t seed) {
  const detect::DetectorPattern& dp = s.detector.patterns[index];
  const std::string& name = dp.pattern.name;
  const std::string robots =
      d.Describe("robots_per_team") + " is " + std::to_string(s.scene.robots_per_team);
  const int ids = static_cast<int>(dp.codebook.entries.size());
  if (s.scene.robots_per_team > ids) {
    d.Fail("robots_per_team",
           robots + "; expected at most " + std::to_string(ids) + " (the IDs of " + name + ")");
  }
  const int total = static_cast<int>(dp.key_colours.size()) * s.scene.robots_per_team;
  if (const double fraction = ExcludedFraction(s.scene, total);
      !(fraction <= kMaxExcludedFraction)) {
    d.Fail("robots_per_team",
           robots + " (" + name + "): " + std::to_string(total) + " robots " +
               FormatNumber(s.scene.min_separation_mm) + " mm apart" +
               (s.scene.ball ? " and the ball" : "") + " exclude " +
               FormatFixed(100 * fraction, 0) +
               "% of the area their centres are drawn from; expected at most 80% (a larger "
               "field, fewer robots or a smaller min_separation_mm)");
  }
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
    d.Fail("robots_per_team",
           robots + " (" + name + "): " + (what.starts_with("scene: ") ? what.substr(7) : what));
  }
}

// Detect mode: `patterns` name [[pattern]]s of the detector settings.
void ResolveDetectPatterns(const TomlReader& r, const TomlReader& d, const toml::array& patterns,
                           Experiment* e) {
  DetectSettings& s = e->detect;
  for (const toml::node& item : patterns) {
    const std::string& name = item.as_string()->get();
    const FileLoc loc = io::LocOf(r.file(), item);
    std::string names;
    const int index = FindDetectorPattern(s.detector, name, &names);
    if (index < 0) {
      throw InputError(loc, "pattern '" + name + "' is not in the detector settings " +
                                s.settings_file + "; expected one of: " + names);
    }
    CheckNotListed(e->patterns, name, loc);
    CheckSceneFits(d, s, index, e->seed);
    e->patterns.push_back(s.detector.patterns[index].pattern);
    e->pattern_files.push_back(s.settings_file);
    s.detector_pattern.push_back(index);
  }
}

void ReadDetectMode(const TomlReader& r, const toml::array& patterns, const fs::path& base,
                    Experiment* e) {
  if (!r.Has("detect")) {
    r.Fail("detect",
           "missing [detect] with correspondence = \"detect\"; expected a table "
           "with at least settings = \"<detector settings file>\"");
  }
  const TomlReader d(SubTable(r, "detect"), r.file(), "[detect]");
  ReadDetectTable(d, base, *e, &e->detect);
  ResolveDetectPatterns(r, d, patterns, e);
}

}  // namespace

Experiment LoadExperimentFile(const std::string& path) {
  const toml::table root = io::ParseTomlFile(path);
  const TomlReader r(root, path);
  Experiment e;
  e.correspondence = r.OptionalString("correspondence") == "detect" ? Correspondence::kDetect
                                                                    : Correspondence::kKnown;
  const bool detect_mode = e.correspondence == Correspondence::kDetect;
  CheckTopLevelKeys(r, detect_mode);
  e.source_file = path;
  e.name = r.String("name");
  if (!io::IsFileBaseName(e.name)) {
    r.Fail("name",
           "name is \"" + EscapeForMessage(e.name) + "\"; expected " + io::kFileBaseNameExpected);
  }
  e.description = r.OptionalString("description").value_or("");
  e.correspondence = ReadCorrespondence(r);
  const fs::path base = fs::path(path).parent_path();

  const toml::array& patterns = ReadPatternList(r);
  if (!detect_mode) {
    LoadKnownPatterns(r, patterns, base, &e);
    e.estimators = ReadEstimators(r);
  }
  ReadTrialsAndSeed(r, &e);
  if (!r.Has("sigma")) {
    r.Fail("sigma", "missing [sigma]; expected a table with values = [...] or from, to, steps");
  }
  e.sigmas_mm = ReadSigmaGrid(TomlReader(SubTable(r, "sigma"), path, "[sigma]"));
  if (r.Has("field")) ReadField(TomlReader(SubTable(r, "field"), path, "[field]"), detect_mode, &e);
  e.noise = ReadNoise(r, base);
  if (detect_mode) ReadDetectMode(r, patterns, base, &e);
  if (r.Has("ml")) e.ml_options = ReadMlTable(TomlReader(SubTable(r, "ml"), path, "[ml]"));
  return e;
}

}  // namespace patlab::sim

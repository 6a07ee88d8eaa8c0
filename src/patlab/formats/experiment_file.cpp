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
#include "patlab/formats/experiment_file_internal.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace internal {

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

void CheckNotListed(const std::vector<Pattern>& seen, const std::string& name, const FileLoc& loc) {
  for (const Pattern& pattern : seen) {
    if (pattern.name == name) {
      throw InputError(loc, "pattern '" + name + "' is listed twice; expected each pattern once");
    }
  }
}

}  // namespace internal

namespace {

namespace fs = std::filesystem;
using internal::CheckNotListed;
using internal::FailAtFirst;
using internal::NonEmptyArray;
using internal::NumberOf;
using internal::ReadDetectMode;
using internal::SubTable;
using io::TomlReader;

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

sim::Correspondence ReadCorrespondence(const TomlReader& r) {
  const auto name = r.OptionalString("correspondence");
  if (!name) return sim::Correspondence::kKnown;
  const auto value = FindName(*name, sim::kCorrespondenceNames);
  if (!value) {
    r.Fail("correspondence",
           "correspondence is \"" + *name + "\"; expected " + NameList(sim::kCorrespondenceNames));
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

// Known mode: pattern names resolve in patterns_dir; a reference with a path separator or .toml
// is a file relative to the experiment file.
void LoadKnownPatterns(const TomlReader& r, const toml::array& patterns, const fs::path& base,
                       sim::Experiment* e) {
  const std::string patterns_dir =
      (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal().string();
  for (const toml::node& item : patterns) {
    std::string reference = item.as_string()->get();
    if (reference.find('/') != std::string::npos || reference.ends_with(".toml")) {
      reference = (base / reference).lexically_normal().string();
    }
    std::string file;
    try {
      file = formats::ResolvePatternPath(reference, patterns_dir);
    } catch (const InputError& error) {
      throw InputError(io::LocOf(r.file(), item), error.what());
    }
    Pattern pattern = formats::LoadPatternFile(file);
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

void ReadTrialsAndSeed(const TomlReader& r, sim::Experiment* e) {
  if (const auto trials = r.OptionalInteger("trials")) {
    OptionsChecker check;
    sim::CheckTrials(*trials, "trials", &check);
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
    sim::CheckSigmas(sigmas, "values", &check);
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
void ReadField(const TomlReader& f, bool detect_mode, sim::Experiment* e) {
  f.CheckKeys({"length_mm", "width_mm"});
  e->field_length_mm = f.OptionalNumber("length_mm").value_or(e->field_length_mm);
  e->field_width_mm = f.OptionalNumber("width_mm").value_or(e->field_width_mm);
  OptionsChecker check;
  sim::CheckFieldSides(e->field_length_mm, e->field_width_mm, "length_mm", "width_mm", &check);
  if (detect_mode && check.problems().empty()) {
    sim::SceneOptions scene;
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

sim::NoiseModel ReadNoiseTable(const TomlReader& r) {
  r.CheckKeys({"sigma_y_ratio", "common_sigma_ratio", "outlier_probability", "outlier_sigma_ratio",
               "rotation_jitter_rad", "scale_jitter_ppm", "correlation_length_mm", "key_shift_x_mm",
               "id_shift_x_mm"});
  sim::NoiseModel noise;
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
sim::NoiseModel ReadNoise(const TomlReader& r, const fs::path& base) {
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
  return sim::NoiseModel{};
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

}  // namespace

sim::Experiment LoadExperimentFile(const std::string& path) {
  const toml::table root = io::ParseTomlFile(path);
  const TomlReader r(root, path);
  sim::Experiment e;
  e.correspondence = r.OptionalString("correspondence") == "detect" ? sim::Correspondence::kDetect
                                                                    : sim::Correspondence::kKnown;
  const bool detect_mode = e.correspondence == sim::Correspondence::kDetect;
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

}  // namespace patlab::formats

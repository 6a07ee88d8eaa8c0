#include "sim/experiment.h"

#include <cmath>
#include <filesystem>

#include "io/pattern_file.h"
#include "io/toml_util.h"

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

}  // namespace

Experiment LoadExperimentFile(const std::string& path) {
  const toml::table root = io::ParseTomlFile(path);
  TomlReader r(root, path);
  r.CheckKeys({"name", "description", "patterns", "patterns_dir", "estimators", "trials", "seed",
               "correspondence", "sigma", "field", "noise", "noise_file", "ml"});
  Experiment e;
  e.source_file = path;
  e.name = r.String("name");
  e.description = r.OptionalString("description").value_or("");
  const fs::path base = fs::path(path).parent_path();
  const std::string patterns_dir =
      (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal().string();

  if (const auto corr = r.OptionalString("correspondence"); corr && *corr != "known") {
    r.Fail("correspondence", "correspondence is \"" + *corr + "\"; expected \"known\"");
  }

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
  if (overrides.trials != 0) {
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

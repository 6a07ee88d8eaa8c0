#include "patlab/formats/detector_settings.h"

#include <algorithm>
#include <filesystem>
#include <limits>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/codebook_file.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/toml_values_internal.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

namespace fs = std::filesystem;

// An array of distinct colour names, each resolved to its canonical name (io/colour_vocabulary.h):
// "magenta" and "Pink" are "pink", and so two of them are the same colour listed twice.
std::vector<std::string> StringList(const toml::table& table, std::string_view key,
                                    const std::string& file, const std::string& what) {
  const toml::node* node = table.get(key);
  const toml::array* array = node == nullptr ? nullptr : node->as_array();
  if (array == nullptr || array->empty()) {
    throw InputError(node == nullptr ? io::LocOf(file, table) : io::LocOf(file, *node),
                     (node == nullptr ? "missing " + std::string(key)
                                      : std::string(key) + " is " +
                                            (array == nullptr ? io::TypeName(*node)
                                                              : std::string("an empty array"))) +
                         "; expected a non-empty array of " + what);
  }
  std::vector<std::string> out;
  for (const toml::node& item : *array) {
    const auto* s = item.as_string();
    if (s == nullptr || s->get().empty()) {
      throw InputError(io::LocOf(file, item),
                       std::string(key) + " holds " +
                           (s == nullptr ? io::TypeName(item) : std::string("an empty string")) +
                           "; expected " + what);
    }
    const std::string name = io::CanonicalColour(s->get(), io::LocOf(file, item));
    if (std::find(out.begin(), out.end(), name) != out.end()) {
      throw InputError(io::LocOf(file, item), std::string(key) + " lists \"" + s->get() +
                                                  "\" twice; expected distinct " + what);
    }
    out.push_back(name);
  }
  return out;
}

void CheckInPalette(const std::vector<std::string>& names, const std::vector<std::string>& palette,
                    const toml::table& table, std::string_view key, const std::string& file) {
  for (size_t i = 0; i < names.size(); ++i) {
    if (std::find(palette.begin(), palette.end(), names[i]) != palette.end()) continue;
    const toml::node& item = *table.get(key)->as_array()->get(i);
    std::string list;
    for (const std::string& c : palette) list += (list.empty() ? "" : ", ") + c;
    throw InputError(io::LocOf(file, item),
                     "colour \"" + names[i] + "\" is not in the palette; expected one of: " + list);
  }
}

// A table's missing_patch key, if present: "reject" or "fit".
std::optional<detect::MissingPatchPolicy> OptionalMissingPatch(const io::TomlReader& table) {
  const auto name = table.OptionalString("missing_patch");
  if (!name) return std::nullopt;
  const auto policy = FindName(*name, detect::kMissingPatchPolicyNames);
  if (!policy) {
    table.Fail("missing_patch", "missing_patch is \"" + *name + "\"; expected " +
                                    NameList(detect::kMissingPatchPolicyNames));
  }
  return policy;
}

// [detector]: every field optional, defaults from DetectorOptions; a broken constraint
// (Check) at its key's line.
detect::DetectorOptions ReadDetectorOptions(const toml::table& root, const io::TomlReader& reader,
                                            const std::string& file) {
  detect::DetectorOptions o;
  static const toml::table kEmpty;
  const toml::node* detector_node = root.get("detector");
  if (detector_node != nullptr && !detector_node->is_table()) {
    reader.Fail("detector", "detector is " + io::TypeName(*detector_node) + "; expected a table");
  }
  const toml::table& dt = detector_node != nullptr ? *detector_node->as_table() : kEmpty;
  io::TomlReader dr(dt, file, "[detector]");
  dr.CheckKeys({"patch_sigma_mm", "geometry_confidence", "reach_margin_mm", "area_ratio_min",
                "area_ratio_max", "missing_patch", "max_neighbours", "estimator",
                "ml_max_iterations"});
  o.patch_sigma_mm = dr.OptionalNumber("patch_sigma_mm").value_or(o.patch_sigma_mm);
  o.geometry_confidence = dr.OptionalNumber("geometry_confidence").value_or(o.geometry_confidence);
  o.reach_margin_mm = dr.OptionalNumber("reach_margin_mm").value_or(o.reach_margin_mm);
  o.area_ratio_min = dr.OptionalNumber("area_ratio_min").value_or(o.area_ratio_min);
  o.area_ratio_max = dr.OptionalNumber("area_ratio_max").value_or(o.area_ratio_max);
  // Integers beyond int saturate; the limits themselves are Check's (one per field).
  const auto to_int = [](int64_t v) {
    return static_cast<int>(
        std::clamp<int64_t>(v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  };
  if (auto v = dr.OptionalInteger("max_neighbours")) o.max_neighbours = to_int(*v);
  if (auto v = dr.OptionalInteger("ml_max_iterations")) o.ml.max_iterations = to_int(*v);
  if (auto policy = OptionalMissingPatch(dr)) o.missing_patch = *policy;
  if (auto v = dr.OptionalString("estimator")) {
    // "robust" needs the noise model's sigma and outlier mixture, which a detector's settings
    // do not state: the settings offer the other four.
    if (!estimate::ParseEstimator(*v, &o.estimator) ||
        o.estimator == estimate::Estimator::kRobust) {
      dr.Fail("estimator",
              "estimator is \"" + *v + "\"; expected \"fast\", \"ml\", \"lsq\" or \"key\"");
    }
  }
  const std::vector<OptionsProblem> problems = detect::Check(o);
  if (!problems.empty()) dr.Fail(problems.front().field, problems.front().message);
  return o;
}

// [frame]: every field optional; a bad value at its key's line.
detect::FrameSettings ReadFrameSettings(const toml::table& root, const io::TomlReader& reader,
                                        const std::string& file) {
  detect::FrameSettings f;
  const toml::node* frame_node = root.get("frame");
  if (frame_node == nullptr) return f;
  if (!frame_node->is_table()) {
    reader.Fail("frame", "frame is " + io::TypeName(*frame_node) + "; expected a table");
  }
  io::TomlReader fr(*frame_node->as_table(), file, "[frame]");
  fr.CheckKeys({"edge_loss_px", "missing_patch", "light_luma", "binning"});
  f.edge_loss_px = fr.OptionalNumber("edge_loss_px");
  f.light_luma = fr.OptionalNumber("light_luma");
  f.binning = fr.OptionalInteger("binning");
  f.missing_patch = OptionalMissingPatch(fr);
  const std::vector<OptionsProblem> problems = detect::Check(f);
  if (!problems.empty()) fr.Fail(problems.front().field, problems.front().message);
  return f;
}

// The pattern a [[pattern]] table names: a path (relative to the settings file) or a name in
// patterns_dir. One that cannot be found is reported at its line; a broken pattern file reports
// its own file and line.
Pattern ReadPattern(const io::TomlReader& pr, const std::string& base_dir,
                    const std::string& patterns_dir) {
  const std::string reference = pr.String("pattern");
  try {
    const bool is_path = reference.find('/') != std::string::npos || reference.ends_with(".toml");
    return formats::LoadPatternFile(is_path ? internal::ResolveBeside(base_dir, reference)
                                            : formats::ResolvePatternPath(reference, patterns_dir));
  } catch (const InputError& e) {
    if (std::string(e.what()).starts_with("pattern '")) pr.Fail("pattern", e.what());
    throw;
  }
}

// [[pattern]] table i: its pattern, key colours, and codebook file or ID colours.
detect::DetectorPattern ReadPatternTable(const toml::table& t, size_t i,
                                         const detect::DetectorConfig& config,
                                         const std::string& file, const std::string& base_dir,
                                         const std::string& patterns_dir) {
  io::TomlReader pr(t, file, "[[pattern]] " + std::to_string(i));
  pr.CheckKeys({"pattern", "codebook", "id_colours", "key_colours", "symmetry_tolerance_mm"});
  Pattern pattern = ReadPattern(pr, base_dir, patterns_dir);
  const double symmetry_tolerance_mm =
      pr.OptionalNumber("symmetry_tolerance_mm")
          .value_or(detect::DetectorPattern{}.symmetry_tolerance_mm);
  if (symmetry_tolerance_mm < 0.0) {
    pr.Fail("symmetry_tolerance_mm", "symmetry_tolerance_mm is " +
                                         FormatNumber(symmetry_tolerance_mm) +
                                         "; expected a number >= 0 (mm)");
  }
  std::vector<std::string> key_colours = StringList(t, "key_colours", file, "team colour names");
  CheckInPalette(key_colours, config.palette, t, "key_colours", file);
  const bool has_codebook = pr.Has("codebook");
  const bool has_colours = pr.Has("id_colours");
  if (has_codebook == has_colours) {
    pr.Fail(has_codebook ? "id_colours" : "pattern",
            "[[pattern]] " + std::to_string(i) +
                (has_codebook ? " has both codebook and id_colours"
                              : " has neither codebook nor id_colours") +
                "; expected exactly one of them");
  }
  std::vector<std::string> id_colours;
  if (has_colours) {
    id_colours = StringList(t, "id_colours", file, "ID colour names");
    CheckInPalette(id_colours, config.palette, t, "id_colours", file);
  }
  detect::DetectorPattern dp = MakeDetectorPattern(
      std::move(pattern), std::move(key_colours),
      has_codebook ? internal::ResolveBeside(base_dir, pr.String("codebook")) : std::string(),
      id_colours, symmetry_tolerance_mm);
  for (const std::string& c : dp.codebook.colours) {
    if (std::find(config.palette.begin(), config.palette.end(), c) == config.palette.end()) {
      pr.Fail("codebook", "codebook colour \"" + c +
                              "\" is not in the palette; expected "
                              "the palette to list every codebook colour");
    }
  }
  return dp;
}

}  // namespace

detect::DetectorConfig ParseDetectorSettings(const std::string& text,
                                             const std::string& source_name,
                                             const std::string& base_dir) {
  const toml::table root = io::ParseTomlText(text, source_name);
  io::TomlReader reader(root, source_name);
  reader.CheckKeys({"palette", "patterns_dir", "detector", "frame", "pattern"});
  detect::DetectorConfig config;
  config.palette = StringList(root, "palette", source_name, "colour names");
  if (config.palette.size() > 64) {
    reader.Fail("palette", "palette has " + std::to_string(config.palette.size()) +
                               " colours; expected at most 64");
  }
  const std::string patterns_dir = internal::ResolveBeside(
      base_dir, reader.OptionalString("patterns_dir").value_or("../patterns"));
  config.options = ReadDetectorOptions(root, reader, source_name);
  ReadFrameSettings(root, reader, source_name);  // checked here, applied by the frame front ends

  const toml::node* patterns_node = root.get("pattern");
  const toml::array* patterns = patterns_node == nullptr ? nullptr : patterns_node->as_array();
  if (patterns == nullptr || !patterns->is_array_of_tables() || patterns->empty()) {
    throw InputError(
        patterns_node == nullptr ? FileLoc{source_name, 1} : io::LocOf(source_name, *patterns_node),
        "no patterns; expected at least one [[pattern]] table");
  }
  for (size_t i = 0; i < patterns->size(); ++i) {
    config.patterns.push_back(ReadPatternTable(*patterns->get(i)->as_table(), i, config,
                                               source_name, base_dir, patterns_dir));
  }
  try {
    // The remaining cross-checks (fixed colours, max_neighbours).
    return detect::MakeDetectorConfig(std::move(config.palette), config.options,
                                      std::move(config.patterns));
  } catch (const InputError& e) {
    throw InputError(FileLoc{source_name, 0}, e.what());
  }
}

detect::DetectorPattern MakeDetectorPattern(Pattern pattern, std::vector<std::string> key_colours,
                                            const std::string& codebook_file,
                                            const std::vector<std::string>& id_colours,
                                            double symmetry_tolerance_mm) {
  detect::DetectorPattern dp;
  dp.symmetry_tolerance_mm = symmetry_tolerance_mm;
  dp.key_colours = std::move(key_colours);
  const detect::Symmetry symmetry = detect::FindSymmetry(pattern, symmetry_tolerance_mm);
  dp.codebook = codebook_file.empty() ? detect::GenerateCodebook(pattern, symmetry, id_colours)
                                      : LoadCodebookFile(codebook_file, pattern, symmetry);
  dp.pattern = std::move(pattern);
  return dp;
}

detect::FrameSettings ParseFrameSettings(const std::string& text, const std::string& source_name) {
  const toml::table root = io::ParseTomlText(text, source_name);
  return ReadFrameSettings(root, io::TomlReader(root, source_name), source_name);
}

detect::FrameSettings LoadFrameSettings(const std::string& path) {
  return ParseFrameSettings(io::ReadTextFile(path, "TOML file"), path);
}

detect::DetectorConfig LoadDetectorSettings(const std::string& path) {
  return ParseDetectorSettings(io::ReadTextFile(path, "TOML file"), path,
                               fs::path(path).parent_path().string());
}

}  // namespace patlab::formats

// The [detect] table of experiment files (correspondence = "detect"): the detector settings, the
// scene's numbers, false-blob rates, and checks that each pattern's trial scene fits.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>

#include "patlab/core/format.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/formats/experiment_file_internal.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {
namespace {

namespace fs = std::filesystem;
using internal::CheckNotListed;
using internal::FailAtFirst;
using internal::NumberOf;
using io::TomlReader;

// ---------------------------------------------------------------------------------------------
// [detect]: see DetectSettings.

// settings = "<file>", relative to the experiment; loaded (and checked) as a detector settings
// file.
void ReadDetectorSettings(const TomlReader& d, const fs::path& base, sim::DetectSettings* s) {
  const std::string expected = "expected a detector settings file (relative to the experiment)";
  if (!d.Has("settings")) d.Fail("settings", "missing " + d.Describe("settings") + "; " + expected);
  const std::string settings = d.String("settings");
  s->settings_file = (base / settings).lexically_normal().string();
  std::error_code ec;  // a name the file system refuses is not a file
  if (!fs::is_regular_file(s->settings_file, ec)) {
    d.Fail("settings", d.Describe("settings") + " is \"" + settings + "\", but " +
                           s->settings_file + " is not a file; " + expected);
  }
  s->detector = formats::LoadDetectorSettings(s->settings_file);
}

// The scalar keys: frames, the scene's numbers and switches, match_radius_mm, detector_sigma.
void ReadDetectScalars(const TomlReader& d, sim::DetectSettings* s) {
  s->frames = d.OptionalInteger("frames").value_or(s->frames);
  sim::SceneOptions& o = s->scene;
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
    const auto matched = FindName(*mode, sim::kDetectorSigmaNames);
    if (!matched) {
      d.Fail("detector_sigma", d.Describe("detector_sigma") + " is \"" + *mode + "\"; expected " +
                                   NameList(sim::kDetectorSigmaNames));
    }
    s->matched_sigma = *matched;
  }
}

// false_blob_rate_per_m2: one number, or an array of them (a second grid axis), each checked
// at its own line.
void ReadFalseBlobRates(const TomlReader& d, sim::DetectSettings* s) {
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
  sim::SceneOptions scene = s->scene;
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
void CheckBallColour(const TomlReader& d, const sim::DetectSettings& s) {
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
void ReadDetectTable(const TomlReader& d, const fs::path& base, const sim::Experiment& e,
                     sim::DetectSettings* s) {
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
double ExcludedFraction(const sim::SceneOptions& o, int robots) {
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
void CheckSceneFits(const TomlReader& d, const sim::DetectSettings& s, int index, uint64_t seed) {
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
  sim::SceneOptions scene = s.scene;
  scene.pattern = 0;
  RandomStream rng(seed, 0, 0);
  try {
    sim::GenerateScene(detector, scene, sim::PatchNoise{}, rng);
  } catch (const InputError& error) {
    const std::string what = error.what();
    d.Fail("robots_per_team",
           robots + " (" + name + "): " + (what.starts_with("scene: ") ? what.substr(7) : what));
  }
}

// Detect mode: `patterns` name [[pattern]]s of the detector settings.
void ResolveDetectPatterns(const TomlReader& r, const TomlReader& d, const toml::array& patterns,
                           sim::Experiment* e) {
  sim::DetectSettings& s = e->detect;
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

}  // namespace

namespace internal {

void ReadDetectMode(const TomlReader& r, const toml::array& patterns, const fs::path& base,
                    sim::Experiment* e) {
  if (!r.Has("detect")) {
    r.Fail("detect",
           "missing [detect] with correspondence = \"detect\"; expected a table "
           "with at least settings = \"<detector settings file>\"");
  }
  const TomlReader d(SubTable(r, "detect"), r.file(), "[detect]");
  ReadDetectTable(d, base, *e, &e->detect);
  ResolveDetectPatterns(r, d, patterns, e);
}

}  // namespace internal
}  // namespace patlab::formats

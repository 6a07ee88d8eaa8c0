#include "patlab/formats/track_file.h"

#include <algorithm>
#include <climits>
#include <filesystem>

#include "patlab/core/error.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

int ReadInt(const io::TomlReader& r, std::string_view key, int fallback) {
  const auto v = r.OptionalInteger(key);
  if (!v) return fallback;
  if (*v < INT_MIN / 2 || *v > INT_MAX / 2) {
    r.Fail(key, r.Describe(key) + " is " + std::to_string(*v) + "; expected a smaller integer");
  }
  return static_cast<int>(*v);
}

double ReadNumber(const io::TomlReader& r, std::string_view key, double fallback) {
  return r.OptionalNumber(key).value_or(fallback);
}

// The sub-table [key] of the root, or null when the file has none.
const toml::table* OptionalSubTable(const io::TomlReader& r, std::string_view key) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) return nullptr;
  if (node->as_table() == nullptr) {
    r.Fail(key, std::string(key) + " is " + io::TypeName(*node) + "; expected a table [" +
                    std::string(key) + "]");
  }
  return node->as_table();
}

void ParseTop(const io::TomlReader& r, analysis::TrackOptions* o) {
  o->name = r.OptionalString("name").value_or(o->name);
  if (!io::IsFileBaseName(o->name)) {
    r.Fail("name",
           "name is \"" + EscapeForMessage(o->name) + "\"; expected " + io::kFileBaseNameExpected);
  }
  o->description = r.OptionalString("description").value_or("");
  if (const auto seed = r.OptionalInteger("seed")) {
    if (*seed < 0) {
      r.Fail("seed", "seed is " + std::to_string(*seed) + "; expected an integer >= 0");
    }
    o->seed = static_cast<uint64_t>(*seed);
  }
  o->runs = ReadInt(r, "runs", o->runs);
}

void ParseDiameters(const io::TomlReader& r, analysis::TrackOptions* o) {
  const toml::node* node = r.table().get("diameters_mm");
  if (node == nullptr) return;
  const toml::array* array = node->as_array();
  if (array == nullptr) {
    r.Fail("diameters_mm",
           "diameters_mm is " + io::TypeName(*node) + "; expected an array of diameters (mm)");
  }
  o->diameters_mm.clear();
  for (const toml::node& item : *array) {
    if (const auto* i = item.as_integer()) {
      o->diameters_mm.push_back(static_cast<double>(i->get()));
    } else if (const auto* f = item.as_floating_point()) {
      o->diameters_mm.push_back(f->get());
    } else {
      throw InputError(io::LocOf(r.file(), item),
                       "diameters_mm contains " + io::TypeName(item) + "; expected numbers (mm)");
    }
  }
}

// pattern = "butterfly" (a name in patterns_dir, default ../patterns next to the file) or a
// path relative to the file.
void ParsePattern(const io::TomlReader& r, analysis::TrackOptions* o) {
  const auto pattern = r.OptionalString("pattern");
  if (!pattern || pattern->empty()) return;
  const std::filesystem::path base = std::filesystem::path(r.file()).parent_path();
  const std::string dir =
      (base / r.OptionalString("patterns_dir").value_or("../patterns")).lexically_normal();
  std::string reference = *pattern;
  if (reference.find('/') != std::string::npos || reference.ends_with(".toml")) {
    reference = (base / reference).lexically_normal().string();
  }
  try {
    o->pattern_file = formats::ResolvePatternPath(reference, dir);
  } catch (const InputError& e) {
    throw InputError(r.Loc("pattern"), e.what());
  }
  o->pattern = formats::LoadPatternFile(o->pattern_file);
}

void ParsePlatform(const io::TomlReader& s, analysis::TrackOptions* o) {
  s.CheckKeys({"samples_per_run", "rate_hz", "speed_mm_per_s", "heading_max_deg",
               "lateral_range_mm", "start_jitter_mm", "spacing_mm", "plane_height_mm"});
  o->samples_per_run = ReadInt(s, "samples_per_run", o->samples_per_run);
  o->rate_hz = ReadNumber(s, "rate_hz", o->rate_hz);
  o->speed_mm_per_s = ReadNumber(s, "speed_mm_per_s", o->speed_mm_per_s);
  o->heading_max_deg = ReadNumber(s, "heading_max_deg", o->heading_max_deg);
  o->lateral_range_mm = ReadNumber(s, "lateral_range_mm", o->lateral_range_mm);
  o->start_jitter_mm = ReadNumber(s, "start_jitter_mm", o->start_jitter_mm);
  o->spacing_mm = ReadNumber(s, "spacing_mm", o->spacing_mm);
  o->plane_height_mm = ReadNumber(s, "plane_height_mm", o->plane_height_mm);
}

void ParseCamera(const io::TomlReader& s, analysis::TrackCamera* c) {
  s.CheckKeys({"height_mm", "image_size_px", "focal_length_px"});
  c->height_mm = ReadNumber(s, "height_mm", c->height_mm);
  c->focal_length_px = ReadNumber(s, "focal_length_px", c->focal_length_px);
  const toml::node* node = s.table().get("image_size_px");
  if (node == nullptr) return;
  const toml::array* a = node->as_array();
  if (a == nullptr || a->size() != 2 || !a->get(0)->is_integer() || !a->get(1)->is_integer()) {
    s.Fail("image_size_px",
           "image_size_px in [camera] is not two integers; expected [width, height] (px)");
  }
  auto clamp = [](int64_t v) { return static_cast<int>(std::clamp<int64_t>(v, -1, 1 << 30)); };
  c->image_width_px = clamp(a->get(0)->as_integer()->get());
  c->image_height_px = clamp(a->get(1)->as_integer()->get());
}

void ParseRender(const io::TomlReader& s, analysis::TrackOptions* o) {
  s.CheckKeys({"background_level", "patch_level", "threshold_level", "supersampling"});
  o->background_level = ReadInt(s, "background_level", o->background_level);
  o->patch_level = ReadInt(s, "patch_level", o->patch_level);
  o->threshold_level = ReadInt(s, "threshold_level", o->threshold_level);
  o->supersampling = ReadInt(s, "supersampling", o->supersampling);
}

void ParseNoise(const io::TomlReader& s, analysis::TrackOptions* o) {
  s.CheckKeys({"pixel_sigma", "jitter_sigma_px"});
  o->pixel_sigma = ReadNumber(s, "pixel_sigma", o->pixel_sigma);
  o->jitter_sigma_px = ReadNumber(s, "jitter_sigma_px", o->jitter_sigma_px);
}

void ParseAnalysis(const io::TomlReader& s, analysis::TrackOptions* o) {
  s.CheckKeys({"smoothing_sigma_samples", "trim_samples"});
  o->smoothing_sigma_samples = ReadNumber(s, "smoothing_sigma_samples", o->smoothing_sigma_samples);
  o->trim_samples = ReadInt(s, "trim_samples", o->trim_samples);
}

analysis::TrackOptions ParseTrackTable(const toml::table& root, const std::string& path) {
  const io::TomlReader r(root, path);
  r.CheckKeys({"name", "description", "seed", "runs", "diameters_mm", "pattern", "patterns_dir",
               "platform", "camera", "render", "noise", "analysis"});
  analysis::TrackOptions o;
  o.source_file = path;
  ParseTop(r, &o);
  ParseDiameters(r, &o);
  ParsePattern(r, &o);
  // Each [table] is read by its own parser, in the order of the file format.
  auto section = [&](const char* key, auto parse) {
    if (const toml::table* t = OptionalSubTable(r, key)) {
      parse(io::TomlReader(*t, path, std::string("[").append(key).append("]")));
    }
  };
  section("platform", [&](const io::TomlReader& s) { ParsePlatform(s, &o); });
  section("camera", [&](const io::TomlReader& s) { ParseCamera(s, &o.camera); });
  section("render", [&](const io::TomlReader& s) { ParseRender(s, &o); });
  section("noise", [&](const io::TomlReader& s) { ParseNoise(s, &o); });
  section("analysis", [&](const io::TomlReader& s) { ParseAnalysis(s, &o); });
  io::ThrowFirstProblemAt(root, path, Check(o));
  return o;
}

}  // namespace

analysis::TrackOptions LoadTrackExperiment(const std::string& path) {
  return ParseTrackTable(io::ParseTomlFile(path), path);
}

analysis::TrackOptions ParseTrackExperiment(std::string_view text, const std::string& source_name) {
  return ParseTrackTable(io::ParseTomlText(text, source_name), source_name);
}

}  // namespace patlab::formats

// Parsing of calibration-input files (calibrate.h, docs/file-formats.md#calibration-input).
#include <cmath>
#include <filesystem>

#include "patlab/calib/calibrate.h"
#include "patlab/core/format.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/toml_values_internal.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

namespace in = internal;
constexpr const char* kPixel = "[u, v] in pixels";
constexpr const char* kPixels = "an array of [u, v] pixel pairs";
constexpr const char* kWorld = "[x, y] in mm";

std::string Relative(const std::string& base_dir, const std::string& reference) {
  const std::filesystem::path p(reference);
  if (p.is_absolute() || base_dir.empty()) return reference;
  return (std::filesystem::path(base_dir) / p).string();
}

// The plane height of an observation: height_mm, default 0 (the floor); must be in front of the
// camera, which the fit checks; here only a range that can be a field or a robot.
double Height(const io::TomlReader& r) {
  const double h = r.OptionalNumber("height_mm").value_or(0.0);
  if (!(std::abs(h) <= 10000.0))
    r.Fail("height_mm", r.Describe("height_mm") + " is " + FormatNumber(h) +
                            "; expected a plane height within +-10000 mm");
  return h;
}

// A named feature of the field, or the keys that give it explicitly; never both.
bool UsesFeature(const io::TomlReader& r, const calib::Field* field,
                 std::string_view explicit_key) {
  const bool named = r.Has("feature"), given = r.Has(explicit_key);
  if (named == given)
    r.Fail("feature", std::string(named ? "both feature and " : "neither feature nor ") +
                          r.Describe(explicit_key) +
                          "; expected exactly one: a field feature name or coordinates");
  if (named && field == nullptr)
    r.Fail("feature", r.Describe("feature") +
                          " names a field feature but the file sets no field; expected "
                          "field = \"<field file>\" at the top");
  return named;
}

void ReadPoint(const io::TomlReader& r, const calib::Field* field, calib::CalibrationInput& input) {
  r.CheckKeys({"feature", "world_mm", "height_mm", "pixel"});
  calib::PointObservation p;
  p.loc = r.TableLoc();
  if (UsesFeature(r, field, "world_mm")) {
    p.name = r.String("feature");
    const calib::FieldPoint* f = field->FindPoint(p.name);
    if (f == nullptr)
      r.Fail("feature", "point feature '" + p.name + "' is not in field '" + field->name +
                            "'; expected one of: " + field->PointNames());
    p.world_mm = f->at_mm;
  } else {
    p.world_mm = in::ReadPair(r, "world_mm", kWorld);
  }
  p.height_mm = Height(r);
  p.pixel = in::ReadPair(r, "pixel", kPixel);
  input.points.push_back(p);
}

void ReadLine(const io::TomlReader& r, const calib::Field* field, calib::CalibrationInput& input) {
  r.CheckKeys({"feature", "from_mm", "to_mm", "height_mm", "pixels"});
  calib::LineObservation l;
  l.loc = r.TableLoc();
  if (UsesFeature(r, field, "from_mm")) {
    l.name = r.String("feature");
    const calib::FieldLine* f = field->FindLine(l.name);
    if (f == nullptr)
      r.Fail("feature", "line feature '" + l.name + "' is not in field '" + field->name +
                            "'; expected one of: " + field->LineNames());
    l.from_mm = f->from_mm;
    l.to_mm = f->to_mm;
  } else {
    l.from_mm = in::ReadPair(r, "from_mm", kWorld);
    l.to_mm = in::ReadPair(r, "to_mm", kWorld);
    if ((l.to_mm - l.from_mm).norm() < 1.0)
      r.Fail("to_mm", r.Describe("to_mm") +
                          " is within 1 mm of from_mm; expected two distinct points of the line");
  }
  l.height_mm = Height(r);
  l.pixels = in::ReadPairList(r, "pixels", kPixels);
  input.lines.push_back(l);
}

void ReadCircle(const io::TomlReader& r, const calib::Field* field,
                calib::CalibrationInput& input) {
  r.CheckKeys({"feature", "centre_mm", "radius_mm", "height_mm", "pixels"});
  calib::CircleObservation c;
  c.loc = r.TableLoc();
  if (UsesFeature(r, field, "centre_mm")) {
    c.name = r.String("feature");
    const calib::FieldCircle* f = field->FindCircle(c.name);
    if (f == nullptr)
      r.Fail("feature", "circle feature '" + c.name + "' is not in field '" + field->name +
                            "'; expected one of: " + field->CircleNames());
    c.centre_mm = f->centre_mm;
    c.radius_mm = f->radius_mm;
  } else {
    c.centre_mm = in::ReadPair(r, "centre_mm", kWorld);
    c.radius_mm = r.Number("radius_mm");
    if (!(c.radius_mm >= 1.0))
      r.Fail("radius_mm", r.Describe("radius_mm") + " is " + FormatNumber(c.radius_mm) +
                              "; expected a radius of at least 1 mm");
  }
  c.height_mm = Height(r);
  c.pixels = in::ReadPairList(r, "pixels", kPixels);
  input.circles.push_back(c);
}

// pixels = [[u, v], "missing", ...]: one entry per patch of the pattern, in its order.
std::vector<std::optional<Vec2>> PatchPixels(const io::TomlReader& r, int patches) {
  const std::string expected = "one [u, v] pixel pair or \"missing\" per patch of the pattern (" +
                               std::to_string(patches) + ")";
  const toml::array* a = r.table().get("pixels") ? r.table().get("pixels")->as_array() : nullptr;
  if (a == nullptr || static_cast<int>(a->size()) != patches)
    r.Fail("pixels", r.Describe("pixels") + " is malformed; expected " + expected);
  std::vector<std::optional<Vec2>> out;
  for (const toml::node& e : *a) {
    if (const auto* s = e.as_string(); s && s->get() == "missing") {
      out.emplace_back(std::nullopt);
      continue;
    }
    const auto pair = in::PairOf(e);
    if (!pair)
      throw InputError(io::LocOf(r.file(), e), "an element of " + r.Describe("pixels") +
                                                   " is malformed; expected " + expected);
    out.emplace_back(*pair);
  }
  return out;
}

void ReadPattern(const io::TomlReader& r, const std::string& base_dir,
                 calib::CalibrationInput& input) {
  r.CheckKeys({"pattern", "height_mm", "pixels"});
  calib::PatternObservation p;
  p.loc = r.TableLoc();
  const std::string file = Relative(base_dir, r.String("pattern"));
  p.pattern = formats::LoadPatternFile(file);
  p.name = p.pattern.name;
  p.height_mm = Height(r);
  p.pixels = PatchPixels(r, p.pattern.size());
  int seen = 0;
  for (const auto& px : p.pixels) seen += px.has_value();
  if (seen < 2)
    r.Fail("pixels", r.Describe("pixels") + " gives " + std::to_string(seen) +
                         " patch pixels; expected at least 2 (a pattern's pose has 3 unknowns)");
  input.patterns.push_back(std::move(p));
}

void ReadFit(const toml::table& root, const std::string& name, calib::FitOptions& o) {
  const toml::table* t = root["fit"].as_table();
  if (t == nullptr) return;
  const io::TomlReader r(*t, name, "[fit]");
  r.CheckKeys({"fix", "focal_px", "principal_point_px", "k1", "k2", "huber_px", "max_iterations",
               "camera_height_mm", "camera_height_sd_mm", "holdout_folds"});
  if (const toml::node* fix = t->get("fix")) {
    const toml::array* a = fix->as_array();
    if (a == nullptr) r.Fail("fix", "fix in [fit] is not an array; expected names of parameters");
    o.fixed.clear();
    for (const toml::node& e : *a) {
      const auto* s = e.as_string();
      const auto p = s ? FindName(s->get(), calib::kFitParameterNames) : std::nullopt;
      if (!p)
        throw InputError(io::LocOf(name, e),
                         "fix in [fit] holds an unknown parameter; expected "
                         "any of: " +
                             NameList(calib::kFitParameterNames));
      o.fixed.push_back(*p);
    }
  }
  o.focal_px = r.OptionalNumber("focal_px");
  if (o.focal_px && !(*o.focal_px > 0.0))
    r.Fail("focal_px", "focal_px in [fit] is " + FormatNumber(*o.focal_px) + "; expected > 0");
  if (r.Has("principal_point_px"))
    o.principal_point_px = in::ReadPair(r, "principal_point_px", kPixel);
  o.k1 = r.OptionalNumber("k1").value_or(0.0);
  o.k2 = r.OptionalNumber("k2").value_or(0.0);
  o.huber_px = r.OptionalNumber("huber_px").value_or(0.0);
  if (!(o.huber_px >= 0.0))
    r.Fail("huber_px", "huber_px in [fit] is " + FormatNumber(o.huber_px) +
                           "; expected >= 0 (0 = plain least squares)");
  o.camera_height_mm = r.OptionalNumber("camera_height_mm");
  if (o.camera_height_mm && !(*o.camera_height_mm > 0.0 && *o.camera_height_mm <= 100000.0))
    r.Fail("camera_height_mm",
           "camera_height_mm in [fit] is " + FormatNumber(*o.camera_height_mm) +
               "; expected the camera's height above the floor, 0 to 100000 mm");
  o.camera_height_sd_mm = r.OptionalNumber("camera_height_sd_mm").value_or(10.0);
  if (!(o.camera_height_sd_mm > 0.0))
    r.Fail("camera_height_sd_mm", "camera_height_sd_mm in [fit] is " +
                                      FormatNumber(o.camera_height_sd_mm) + "; expected > 0 mm");
  const int64_t it = r.OptionalInteger("max_iterations").value_or(200);
  if (it < 1 || it > 100000)
    r.Fail("max_iterations",
           "max_iterations in [fit] is " + std::to_string(it) + "; expected 1 to 100000");
  o.max_iterations = static_cast<int>(it);
  const int64_t folds = r.OptionalInteger("holdout_folds").value_or(5);
  if (folds != 0 && (folds < 2 || folds > 1000))
    r.Fail("holdout_folds", "holdout_folds in [fit] is " + std::to_string(folds) +
                                "; expected 0 (no held-out error) or 2 to 1000");
  o.holdout_folds = static_cast<int>(folds);
}

void ReadHeights(const toml::table& root, const std::string& name, calib::CalibrationInput& input) {
  const toml::table* t = root["heights"].as_table();
  if (t == nullptr) return;
  const io::TomlReader r(*t, name, "[heights]");
  for (const auto& [key, node] : *t) {
    const double v = r.Number(key.str());
    if (key.str() == "default_mm") {
      input.default_height_mm = v;
    } else {
      input.class_height_mm[std::string(key.str())] = v;
    }
  }
}

void ReadImageSize(const io::TomlReader& top, calib::CalibrationInput& input) {
  const Vec2 size = in::ReadPair(top, "image_size_px", "[width, height] in pixels");
  if (size.x() < 1 || size.y() < 1 || size.x() > 65535 || size.y() > 65535 ||
      size.x() != std::floor(size.x()) || size.y() != std::floor(size.y()))
    top.Fail("image_size_px",
             "image_size_px is not two integers from 1 to 65535; expected [width, height] in "
             "pixels");
  input.image_width_px = static_cast<int>(size.x());
  input.image_height_px = static_cast<int>(size.y());
}

}  // namespace

calib::CalibrationInput ParseCalibrationInput(std::string_view text, const std::string& name,
                                              const std::string& base_dir) {
  const toml::table root = io::ParseTomlText(text, name);
  const io::TomlReader top(root, name);
  top.CheckKeys(
      {"source", "image_size_px", "field", "fit", "heights", "point", "line", "circle", "pattern"});
  calib::CalibrationInput input;
  input.loc = FileLoc{name, 0};
  input.source = top.OptionalString("source").value_or("");
  ReadImageSize(top, input);
  std::optional<calib::Field> field;
  if (const auto f = top.OptionalString("field")) field = LoadField(Relative(base_dir, *f));
  const calib::Field* fp = field ? &*field : nullptr;
  for (const toml::table* t : in::TableArray(root, "point", name))
    ReadPoint(io::TomlReader(*t, name, "[[point]] " + std::to_string(input.points.size() + 1)), fp,
              input);
  for (const toml::table* t : in::TableArray(root, "line", name))
    ReadLine(io::TomlReader(*t, name, "[[line]] " + std::to_string(input.lines.size() + 1)), fp,
             input);
  for (const toml::table* t : in::TableArray(root, "circle", name))
    ReadCircle(io::TomlReader(*t, name, "[[circle]] " + std::to_string(input.circles.size() + 1)),
               fp, input);
  for (const toml::table* t : in::TableArray(root, "pattern", name))
    ReadPattern(
        io::TomlReader(*t, name, "[[pattern]] " + std::to_string(input.patterns.size() + 1)),
        base_dir, input);
  ReadFit(root, name, input.options);
  ReadHeights(root, name, input);
  return input;
}

calib::CalibrationInput LoadCalibrationInput(const std::string& path) {
  const std::string text = io::ReadTextFile(path, "calibration input TOML file");
  return ParseCalibrationInput(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace patlab::formats

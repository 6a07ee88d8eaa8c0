#include "patlab/formats/field_file.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/toml_values_internal.h"
#include "patlab/io/data_path.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

// The feature's name, unique over the whole field so that observations can name it.
std::string UniqueName(const io::TomlReader& r, std::set<std::string>& seen) {
  std::string name = r.String("name");
  if (name.empty()) r.Fail("name", r.Describe("name") + " is empty; expected a feature name");
  if (!seen.insert(name).second)
    r.Fail("name", "name '" + name + "' repeats an earlier feature; expected unique names");
  return name;
}

// An arc's from_deg and to_deg: both or neither (the full circle), from < to <= from + 360.
void ReadArcExtent(const io::TomlReader& r, calib::FieldCircle& c) {
  const std::optional<double> from = r.OptionalNumber("from_deg");
  const std::optional<double> to = r.OptionalNumber("to_deg");
  if (!from && !to) return;
  if (!from || !to) {
    const char* given = from ? "from_deg" : "to_deg";
    r.Fail(given, r.Describe(given) +
                      " is given alone; expected both from_deg and to_deg (an arc) or neither "
                      "(the full circle)");
  }
  if (!std::isfinite(*from) || std::abs(*from) > 720.0)
    r.Fail("from_deg", r.Describe("from_deg") + " is " + FormatNumber(*from) +
                           "; expected an angle in degrees within [-720, 720]");
  if (!(*to > *from && *to <= *from + 360.0))
    r.Fail("to_deg", r.Describe("to_deg") + " is " + FormatNumber(*to) +
                         "; expected more than from_deg (" + FormatNumber(*from) +
                         ") and at most from_deg + 360 (the arc runs anticlockwise)");
  c.from_deg = *from;
  c.to_deg = *to;
}

// The model's optional facts; sizes, when given, positive (the boundary may be 0).
void ReadFacts(const io::TomlReader& top, calib::Field& field) {
  field.family = top.OptionalString("family").value_or("");
  if (const std::optional<int64_t> year = top.OptionalInteger("year")) {
    if (*year < 1997 || *year > 2200)
      top.Fail("year", top.Describe("year") + " is " + std::to_string(*year) +
                           "; expected the first year of the field's rules (1997 or later)");
    field.year = static_cast<int>(*year);
  }
  const auto positive = [&](const char* key, double* out) {
    const std::optional<double> v = top.OptionalNumber(key);
    if (!v) return;
    if (!(*v > 0.0) || !std::isfinite(*v))
      top.Fail(key, top.Describe(key) + " is " + FormatNumber(*v) + "; expected a length > 0 mm");
    *out = *v;
  };
  positive("length_mm", &field.length_mm);
  positive("width_mm", &field.width_mm);
  positive("goal_width_mm", &field.goal_width_mm);
  positive("goal_depth_mm", &field.goal_depth_mm);
  if (const std::optional<double> b = top.OptionalNumber("boundary_mm")) {
    if (!(*b >= 0.0) || !std::isfinite(*b))
      top.Fail("boundary_mm", top.Describe("boundary_mm") + " is " + FormatNumber(*b) +
                                  "; expected a width >= 0 mm");
    field.boundary_mm = *b;
  }
}

void ReadFeatures(const toml::table& root, const std::string& file, calib::Field& field) {
  namespace in = internal;
  std::set<std::string> seen;
  const auto lines = in::TableArray(root, "line", file);
  for (size_t i = 0; i < lines.size(); ++i) {
    const io::TomlReader r(*lines[i], file, "[[line]] " + std::to_string(i + 1));
    r.CheckKeys({"name", "from_mm", "to_mm"});
    calib::FieldLine l{UniqueName(r, seen), in::ReadPair(r, "from_mm", "[x, y] in mm"),
                       in::ReadPair(r, "to_mm", "[x, y] in mm")};
    if ((l.to_mm - l.from_mm).norm() < 1.0)
      r.Fail("to_mm", r.Describe("to_mm") +
                          " is within 1 mm of from_mm; expected two distinct points of the line");
    field.lines.push_back(l);
  }
  const auto circles = in::TableArray(root, "circle", file);
  for (size_t i = 0; i < circles.size(); ++i) {
    const io::TomlReader r(*circles[i], file, "[[circle]] " + std::to_string(i + 1));
    r.CheckKeys({"name", "centre_mm", "radius_mm", "from_deg", "to_deg"});
    calib::FieldCircle c{UniqueName(r, seen), in::ReadPair(r, "centre_mm", "[x, y] in mm"),
                         r.Number("radius_mm")};
    if (!(c.radius_mm >= 1.0))
      r.Fail("radius_mm", r.Describe("radius_mm") + " is " + FormatNumber(c.radius_mm) +
                              "; expected a radius of at least 1 mm");
    ReadArcExtent(r, c);
    field.circles.push_back(c);
  }
  const auto points = in::TableArray(root, "point", file);
  for (size_t i = 0; i < points.size(); ++i) {
    const io::TomlReader r(*points[i], file, "[[point]] " + std::to_string(i + 1));
    r.CheckKeys({"name", "at_mm"});
    field.points.push_back({UniqueName(r, seen), in::ReadPair(r, "at_mm", "[x, y] in mm")});
  }
}

}  // namespace

calib::Field ParseField(std::string_view text, const std::string& source_name) {
  const toml::table root = io::ParseTomlText(text, source_name);
  const io::TomlReader top(root, source_name);
  top.CheckKeys({"name", "source", "family", "year", "length_mm", "width_mm", "boundary_mm",
                 "goal_width_mm", "goal_depth_mm", "line", "circle", "point"});
  calib::Field field;
  field.name = top.String("name");
  field.source = top.OptionalString("source").value_or("");
  ReadFacts(top, field);
  ReadFeatures(root, source_name, field);
  if (field.lines.empty() && field.circles.empty() && field.points.empty()) {
    throw InputError(FileLoc{source_name, 0},
                     "the field has no features; expected [[line]], [[circle]] or [[point]] "
                     "tables");
  }
  return field;
}

calib::Field LoadField(const std::string& path) {
  return ParseField(io::ReadTextFile(path, "field geometry TOML file"), path);
}

std::vector<calib::Field> ShippedFields(const std::vector<std::string>& roots) {
  std::vector<calib::Field> fields;
  for (const std::string& name : io::DataNames(io::DataKind::kField, roots)) {
    fields.push_back(LoadField(io::FindData(name, io::DataKind::kField, roots)));
  }
  std::stable_sort(fields.begin(), fields.end(), [](const calib::Field& a, const calib::Field& b) {
    if (a.family != b.family) return a.family < b.family;
    if (a.year != b.year) return a.year > b.year;
    return a.name < b.name;
  });
  return fields;
}

std::vector<std::string> FieldFamilies(const std::vector<std::string>& roots) {
  std::set<std::string> families;
  for (const calib::Field& f : ShippedFields(roots)) {
    if (!f.family.empty()) families.insert(f.family);
  }
  return {families.begin(), families.end()};
}

std::vector<calib::Field> FieldFamily(std::string_view family,
                                      const std::vector<std::string>& roots) {
  std::vector<calib::Field> out;
  for (calib::Field& f : ShippedFields(roots)) {
    if (f.family == family) out.push_back(std::move(f));
  }
  return out;
}

SetupFieldModels SetupFields(const std::string& name, const std::vector<std::string>& roots) {
  SetupFieldModels models;
  models.fields = FieldFamily(name, roots);
  if (!models.fields.empty()) return models;
  models.fields.push_back(LoadField(io::FindData(name, io::DataKind::kField, roots)));
  const calib::Field& named = models.fields.front();
  if (named.family.empty()) return models;
  for (calib::Field& f : FieldFamily(named.family, roots)) {
    if (f.name != named.name) models.lenders.push_back(std::move(f));
  }
  return models;
}

}  // namespace patlab::formats

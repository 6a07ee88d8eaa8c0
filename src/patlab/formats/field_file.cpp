#include "patlab/formats/field_file.h"

#include <algorithm>
#include <set>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/toml_values_internal.h"
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
    r.CheckKeys({"name", "centre_mm", "radius_mm"});
    calib::FieldCircle c{UniqueName(r, seen), in::ReadPair(r, "centre_mm", "[x, y] in mm"),
                         r.Number("radius_mm")};
    if (!(c.radius_mm >= 1.0))
      r.Fail("radius_mm", r.Describe("radius_mm") + " is " + FormatNumber(c.radius_mm) +
                              "; expected a radius of at least 1 mm");
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
  top.CheckKeys({"name", "source", "line", "circle", "point"});
  calib::Field field;
  field.name = top.String("name");
  field.source = top.OptionalString("source").value_or("");
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

}  // namespace patlab::formats

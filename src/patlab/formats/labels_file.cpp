#include "patlab/formats/labels_file.h"

#include <algorithm>
#include <filesystem>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/name.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

namespace fs = std::filesystem;

// An array of `count` integers at `node`, or nullopt.
template <size_t kCount>
std::optional<std::array<int, kCount>> IntArray(const toml::node& node) {
  const toml::array* a = node.as_array();
  if (a == nullptr || a->size() != kCount) return std::nullopt;
  std::array<int, kCount> out{};
  for (size_t k = 0; k < kCount; ++k) {
    const auto* v = (*a)[k].as_integer();
    if (v == nullptr || v->get() < -1000000 || v->get() > 1000000) return std::nullopt;
    out[k] = static_cast<int>(v->get());
  }
  return out;
}

std::array<uint8_t, 3> ReadRgb(const io::TomlReader& r, std::string_view key,
                               const std::string& context) {
  const auto rgb = IntArray<3>(*r.table().get(key));
  const bool ok =
      rgb && std::all_of(rgb->begin(), rgb->end(), [](int v) { return v >= 0 && v <= 255; });
  if (!ok) {
    r.Fail(key, std::string(key) + " in " + context +
                    " is not [R, G, B]; expected three integers in 0..255");
  }
  return {static_cast<uint8_t>((*rgb)[0]), static_cast<uint8_t>((*rgb)[1]),
          static_cast<uint8_t>((*rgb)[2])};
}

// `key` = [[x, y], ...] (kCount 2) or [[x0, y0, x1, y1], ...] (kCount 4), with each item's line.
template <size_t kCount>
void ReadCoordinateList(const io::TomlReader& r, std::string_view key, const std::string& context,
                        std::vector<std::array<int, kCount>>* items, std::vector<int>* lines) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) return;
  const char* form = kCount == 2 ? "[[x, y], ...]" : "[[x0, y0, x1, y1], ...]";
  const toml::array* list = node->as_array();
  if (list == nullptr) {
    r.Fail(key,
           std::string(key) + " in " + context + " is not a list; expected " + form + " in pixels");
  }
  for (const toml::node& item : *list) {
    const auto value = IntArray<kCount>(item);
    const FileLoc loc = io::LocOf(r.file(), item);
    if (!value) {
      throw InputError(loc, "an item of " + std::string(key) + " in " + context + " is not " +
                                (kCount == 2 ? "[x, y]" : "[x0, y0, x1, y1]") + "; expected " +
                                form + " with integer pixel coordinates");
    }
    if constexpr (kCount == 4) {
      const auto& v = *value;
      if (v[0] > v[2] || v[1] > v[3]) {
        throw InputError(loc, "rectangle [" + std::to_string(v[0]) + ", " + std::to_string(v[1]) +
                                  ", " + std::to_string(v[2]) + ", " + std::to_string(v[3]) +
                                  "] in " + context + " is empty; expected x0 <= x1 and y0 <= y1");
      }
    }
    items->push_back(*value);
    lines->push_back(loc.line);
  }
}

vision::LabelClass ReadLabelClass(const toml::node& node, const std::string& file, size_t index,
                                  const std::vector<vision::LabelClass>& before) {
  const std::string context = "[[class]] " + std::to_string(index + 1);
  const toml::table* table = node.as_table();
  if (table == nullptr) {
    throw InputError(io::LocOf(file, node), context + " is not a table; expected [[class]] tables");
  }
  const io::TomlReader r(*table, file, context);
  r.CheckKeys({"name", "display", "points", "rects", "mask", "min_area_px", "max_area_px"});
  vision::LabelClass c;
  c.line = r.TableLoc().line;
  c.name = r.String("name");
  if (c.name.empty()) r.Fail("name", "empty name in " + context + "; expected a class name");
  if (const std::string problem = io::NameProblem(c.name); !problem.empty()) {
    r.Fail("name", "name '" + EscapeForMessage(c.name) + "' " + problem + "; expected " +
                       io::kNameExpected);
  }
  c.name = io::CanonicalClassName(c.name, r.Loc("name"));
  for (const vision::LabelClass& b : before) {
    if (b.name == c.name) {
      r.Fail("name",
             "duplicate class name \"" + EscapeForMessage(c.name) + "\"; expected unique names");
    }
  }
  if (r.Has("display")) {
    c.has_display = true;
    c.display_rgb = ReadRgb(r, "display", context);
  }
  if (r.Has("mask")) {
    c.has_mask_rgb = true;
    c.mask_rgb = ReadRgb(r, "mask", context);
  }
  ReadCoordinateList<2>(r, "points", context, &c.points, &c.point_lines);
  ReadCoordinateList<4>(r, "rects", context, &c.rectangles, &c.rectangle_lines);
  for (auto [key, field] :
       {std::pair{"min_area_px", &c.min_area_px}, std::pair{"max_area_px", &c.max_area_px}}) {
    if (auto v = r.OptionalInteger(key)) {
      if (*v < 0 || *v > 100000000)
        r.Fail(key, std::string(key) + " " + std::to_string(*v) + " in " + context +
                        "; expected 0..100000000");
      *field = static_cast<int>(*v);
    }
  }
  if (c.max_area_px > 0 && c.max_area_px < c.min_area_px) {
    r.Fail("max_area_px", "max_area_px " + std::to_string(c.max_area_px) + " in " + context +
                              "; expected 0 (no limit) or >= min_area_px");
  }
  if (c.points.empty() && c.rectangles.empty() && !c.has_mask_rgb) {
    throw InputError(FileLoc{file, c.line}, "class \"" + EscapeForMessage(c.name) +
                                                "\" has no samples; expected points, rects or "
                                                "a mask colour");
  }
  return c;
}

std::string ResolveLabelPath(const std::string& base_dir, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() || base_dir.empty() ? path : (fs::path(base_dir) / p).string();
}

}  // namespace

vision::Labels ParseLabels(std::string_view text, const std::string& name,
                           const std::string& base_dir) {
  const toml::table root = io::ParseTomlText(text, name);
  const io::TomlReader top(root, name);
  top.CheckKeys({"image", "mask", "point_radius_px", "class"});
  vision::Labels labels;
  labels.source = name;
  labels.image_path = ResolveLabelPath(base_dir, top.String("image"));
  labels.image_line = top.Loc("image").line;
  if (auto mask = top.OptionalString("mask")) {
    labels.mask_path = ResolveLabelPath(base_dir, *mask);
    labels.mask_line = top.Loc("mask").line;
  }
  if (auto radius = top.OptionalInteger("point_radius_px")) {
    if (*radius < 0 || *radius > 100) {
      top.Fail("point_radius_px",
               "point_radius_px " + std::to_string(*radius) + "; expected 0..100");
    }
    labels.point_radius_px = static_cast<int>(*radius);
  }
  const toml::node* classes_node = root.get("class");
  const toml::array* classes = classes_node ? classes_node->as_array() : nullptr;
  if (classes == nullptr || classes->empty()) {
    throw InputError(FileLoc{name, classes_node ? io::LocOf(name, *classes_node).line : 0},
                     "no classes; expected at least one [[class]] table");
  }
  if (classes->size() > vision::kMaxColorClasses) {
    throw InputError(io::LocOf(name, (*classes)[vision::kMaxColorClasses]),
                     "[[class]] " + std::to_string(vision::kMaxColorClasses + 1) +
                         "; expected at most " + std::to_string(vision::kMaxColorClasses) +
                         " colour classes");
  }
  for (size_t i = 0; i < classes->size(); ++i) {
    labels.classes.push_back(ReadLabelClass((*classes)[i], name, i, labels.classes));
  }
  for (const vision::LabelClass& c : labels.classes) {
    if (c.has_mask_rgb && labels.mask_path.empty()) {
      throw InputError(FileLoc{name, c.line}, "class \"" + EscapeForMessage(c.name) +
                                                  "\" has a mask colour but the file names no "
                                                  "mask; expected mask = \"FILE.png\"");
    }
  }
  return labels;
}

vision::Labels LoadLabels(const std::string& path) {
  const std::string text = io::ReadTextFile(path, "labels file");
  return ParseLabels(text, path, fs::path(path).parent_path().string());
}

}  // namespace patlab::formats

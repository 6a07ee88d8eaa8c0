// patlab.Pattern: a pattern file's contents, patches as numpy arrays.
#include "patlab/core/pattern.h"

#include <cstdlib>
#include <filesystem>

#include "patlab/core/enum_names.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/data_path.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

template <typename F>
std::vector<double> PerPatch(const Pattern& p, int width, F value) {
  std::vector<double> out;
  out.reserve(static_cast<size_t>(p.size() * width));
  for (const Patch& patch : p.patches) value(patch, &out);
  return out;
}

py::array_t<double> Positions(const Pattern& p) {
  return ArrayOf(PerPatch(p, 2,
                          [](const Patch& q, std::vector<double>* out) {
                            out->push_back(q.position_mm.x());
                            out->push_back(q.position_mm.y());
                          }),
                 {p.size(), 2});
}

py::array_t<double> Radii(const Pattern& p) {
  return ArrayOf(
      PerPatch(p, 1, [](const Patch& q, std::vector<double>* out) { out->push_back(q.radius_mm); }),
      {p.size()});
}

std::vector<std::string> Roles(const Pattern& p) {
  std::vector<std::string> roles;
  for (const Patch& q : p.patches) roles.emplace_back(NameOf(q.role, kPatchRoleNames));
  return roles;
}

std::vector<std::string> Shapes(const Pattern& p) {
  std::vector<std::string> shapes;
  for (const Patch& q : p.patches) shapes.emplace_back(NameOf(q.shape, kPatchShapeNames));
  return shapes;
}

std::vector<std::string> Colours(const Pattern& p) {
  std::vector<std::string> colours;
  for (const Patch& q : p.patches) colours.push_back(q.colour);
  return colours;
}

py::array_t<int> Pairs(const Pattern& p) {
  py::array_t<int> pairs({static_cast<py::ssize_t>(p.orientation_pairs.size()), py::ssize_t{2}});
  auto view = pairs.mutable_unchecked<2>();
  for (size_t i = 0; i < p.orientation_pairs.size(); ++i) {
    view(i, 0) = p.orientation_pairs[i].from;
    view(i, 1) = p.orientation_pairs[i].to;
  }
  return pairs;
}

// The kinds of shipped data, as python/patlab/_data.py names them.
inline constexpr EnumNames<io::DataKind, 4> kDataKindNames{{{
    {io::DataKind::kPattern, "pattern"},
    {io::DataKind::kExperiment, "experiment"},
    {io::DataKind::kSettings, "settings"},
    {io::DataKind::kField, "field"},
}}};

// io::FindData over the roots of `binary_dir` (the build tree, or <prefix>/bin of an install)
// and $PATLAB_DATA, as the CLI finds data; a file found under the working directory is named
// relative to it, as the CLI names it in its reports.
std::string FindData(const std::string& reference, const std::string& kind,
                     const std::string& binary_dir) {
  const std::vector<std::string> roots = io::DataRoots(binary_dir, std::getenv("PATLAB_DATA"));
  const std::string found = io::FindData(reference, ParseName(kind, kDataKindNames, "kind"), roots);
  if (found == reference) return found;
  std::error_code ec;
  const std::filesystem::path relative =
      std::filesystem::path(found).lexically_relative(std::filesystem::current_path(ec));
  if (ec || relative.empty() || *relative.begin() == "..") return found;
  return relative.string();
}

}  // namespace

void BindPattern(py::module_& m) {
  m.def("_find_data", &FindData, py::arg("reference"), py::arg("kind"), py::arg("binary_dir"));
  py::class_<Pattern>(m, "Pattern", "A planar patch pattern (patterns/README.md)")
      .def_static("_load_file", &formats::LoadPatternFile, py::arg("path"))
      .def_static("_parse", &formats::ParsePattern, py::arg("text"), py::arg("source_name"))
      .def_readonly("name", &Pattern::name)
      .def_readonly("description", &Pattern::description)
      .def_readonly("key_index", &Pattern::key_index, "index of the key patch")
      .def_property_readonly("size", &Pattern::size, "number of patches")
      .def_property_readonly("positions_mm", &Positions, "(n, 2) patch centres, model frame (mm)")
      .def_property_readonly("radii_mm", &Radii, "(n,) patch radii (mm; equal-area for rectangles)")
      .def_property_readonly("roles", &Roles, "per patch: 'key', 'id' or 'fixed'")
      .def_property_readonly("shapes", &Shapes, "per patch: 'disc' or 'rectangle'")
      .def_property_readonly("colours", &Colours, "per patch: its fixed or team colour, or ''")
      .def_property_readonly("orientation_pairs", &Pairs, "(k, 2) patch indices (from, to)")
      .def_property_readonly("centroid_mm",
                             [](const Pattern& p) {
                               return ArrayOf({p.Centroid().x(), p.Centroid().y()}, {2});
                             })
      .def_property_readonly("spread_mm2", &Pattern::Spread,
                             "sum of squared distances of the patches from their centroid");
}

}  // namespace patlab::python

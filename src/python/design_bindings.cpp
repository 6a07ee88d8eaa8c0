// patlab.ids, patlab.evaluate and patlab.compare: the calls of `patlab ids`, `patlab evaluate`
// and `patlab compare`, with the GIL released and Ctrl-C checked between runs. evaluate and
// compare return the JSON and CSV texts the CLI writes; python/patlab turns them into tables.
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/compare.h"
#include "patlab/design/evaluate.h"
#include "patlab/detect/codebook.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

// As `patlab ids --tolerance` checks it.
void CheckTolerance(double tolerance_mm) {
  if (!(tolerance_mm >= 0.0) || tolerance_mm > 1e6) {
    throw InputError("tolerance_mm is " + FormatNumber(tolerance_mm) +
                     "; expected a distance in mm >= 0");
  }
}

// The pattern's symmetry about its key and its codebook for the ID colours `colours` (names).
py::dict Ids(const Pattern& pattern, const std::vector<std::string>& colours, double tolerance_mm) {
  CheckTolerance(tolerance_mm);
  if (colours.empty()) throw InputError("colours is empty; expected at least one colour name");
  const detect::Symmetry symmetry = detect::FindSymmetry(pattern, tolerance_mm);
  const detect::Codebook book = detect::GenerateCodebook(pattern, symmetry, colours);
  std::vector<int> ids;
  py::array_t<int> colourings(
      {static_cast<py::ssize_t>(book.entries.size()), static_cast<py::ssize_t>(book.num_slots)});
  auto c = colourings.mutable_unchecked<2>();
  for (size_t e = 0; e < book.entries.size(); ++e) {
    ids.push_back(book.entries[e].id);
    for (int s = 0; s < book.num_slots; ++s) c(e, s) = book.entries[e].colour[s];
  }
  py::dict out;
  out["pattern"] = pattern.name;
  out["colours"] = book.colours;
  out["slots"] = detect::IdSlots(pattern);
  out["ids"] = ids;
  out["colourings"] = colourings;
  out["count"] = detect::CountIds(pattern, symmetry, static_cast<int>(colours.size()));
  out["rotations"] = symmetry.effective_order();
  out["accepted_shifts"] = symmetry.shifts;
  out["effective_shifts"] = symmetry.effective_shifts;
  out["summary"] = detect::SymmetrySummary(symmetry);
  out["table"] = detect::SymmetryTable(symmetry, "  ");
  return out;
}

// EvaluateOptions from the keyword arguments of patlab.evaluate (same names as its fields).
design::EvaluateOptions EvaluateOptionsFrom(const py::dict& kwargs) {
  design::EvaluateOptions o;
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (name == "sigma_mm") {
      o.sigma_mm = value.cast<double>();
    } else if (name == "trials") {
      o.trials = value.cast<int64_t>();
    } else if (name == "colour_counts") {
      o.colour_counts = value.cast<std::vector<int>>();
    } else if (name == "tolerance_mm") {
      o.tolerance_mm = value.cast<double>();
    } else if (name == "sigmas_mm") {
      o.sigmas_mm = value.cast<std::vector<double>>();
    } else if (name == "frames") {
      o.frames = value.cast<int64_t>();
    } else if (name == "id_colours") {
      if (!value.is_none()) o.id_colours = value.cast<int>();
    } else if (name == "seed") {
      o.seed = value.cast<uint64_t>();
    } else if (name == "threads") {
      o.threads = value.cast<int>();
    } else {
      throw InputError("unknown option '" + EscapeForMessage(name) +
                       "'; expected sigma_mm, trials, colour_counts, tolerance_mm, sigmas_mm, "
                       "frames, id_colours, seed or threads");
    }
  }
  CheckTolerance(o.tolerance_mm);
  o.progress = SignalCheck();
  return o;
}

// Each (pattern, file): its report as `patlab evaluate --json` writes it, and as text.
py::tuple Evaluate(const std::vector<std::pair<Pattern, std::string>>& designs,
                   const py::dict& kwargs) {
  const design::EvaluateOptions o = EvaluateOptionsFrom(kwargs);
  design::Validate(o);
  std::vector<design::EvaluationReport> reports;
  std::string text;
  {
    const py::gil_scoped_release nogil;
    for (const auto& [pattern, file] : designs) {
      reports.push_back(design::EvaluatePattern(pattern, file, o));
      text += (text.empty() ? "" : "\n") + design::EvaluationText(reports.back());
    }
  }
  return py::make_tuple(design::EvaluationJson(o, reports), text);
}

// The ranked comparison as `patlab compare` writes it: CSV, JSON and text.
py::tuple Compare(const std::vector<std::pair<Pattern, std::string>>& designs,
                  const std::string& sort_by, const py::dict& kwargs) {
  design::CompareOptions o;
  o.evaluate = EvaluateOptionsFrom(kwargs);
  o.evaluate.progress = nullptr;
  o.sort_by = sort_by;
  o.progress = SignalCheck();
  design::Validate(o);
  design::CompareResult result;
  {
    const py::gil_scoped_release nogil;
    result = design::CompareDesigns(designs, o);
  }
  return py::make_tuple(design::CompareCsv(result), design::CompareJson(result),
                        design::CompareText(result));
}

}  // namespace

void BindDesign(py::module_& m) {
  m.def("_ids", &Ids, py::arg("pattern"), py::arg("colours"), py::arg("tolerance_mm"));
  m.def("_evaluate", &Evaluate, py::arg("designs"), py::arg("options"));
  m.def("_compare", &Compare, py::arg("designs"), py::arg("sort_by"), py::arg("options"));
}

}  // namespace patlab::python

// The compiled part of `import patlab` (python/patlab/__init__.py wraps it; docs/python.md).
#include "python/bindings.h"

PYBIND11_MODULE(_patlab, m) {
  m.doc() = "patlab's library calls; use the package patlab, which wraps this module";
  m.attr("version") = PATLAB_VERSION;
  patlab::python::RegisterErrors(m);
  patlab::python::BindPattern(m);
  patlab::python::BindSimulate(m);
  patlab::python::BindEstimate(m);
  patlab::python::BindStats(m);
  patlab::python::BindDesign(m);
  patlab::python::BindDetect(m);
}

// The pieces of the Python module _patlab (docs/python.md): one Bind* function per part of the
// library, and what they share: the errors and the GIL-free runs that Ctrl-C can interrupt.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <functional>
#include <string>
#include <vector>

#include "patlab/estimate/estimators.h"
#include "patlab/sim/noise.h"

namespace patlab::python {

namespace py = pybind11;

void BindPattern(py::module_& m);
void BindSimulate(py::module_& m);
void BindEstimate(py::module_& m);
void BindStats(py::module_& m);
void BindDesign(py::module_& m);
void BindDetect(py::module_& m);

// patlab::InputError becomes ValueError and EnvironmentError OSError, each with the message the
// CLI prints; an interrupted run becomes the KeyboardInterrupt that Python's handler raised.
void RegisterErrors(py::module_& m);

// Thrown on the calling thread of a long run when PyErr_CheckSignals found a pending signal (its
// exception is then set in Python's error indicator).
struct Interrupted {};

// A progress callback for the runners (called on the calling thread between blocks of work, with
// the GIL released around it): takes the GIL, runs Python's signal handlers and throws
// Interrupted when one raised (Ctrl-C: KeyboardInterrupt).
std::function<void(int, int)> SignalCheck();

// Estimator names ("fast", "ml", "lsq", "key"); InputError naming `field` for another.
std::vector<estimate::Estimator> ParseEstimators(const std::vector<std::string>& names,
                                                 const std::string& field);

// A noise model from a dict of the [noise] keys of an experiment file (sim/noise.h); an unknown
// key is an InputError naming it; the model is validated.
sim::NoiseModel NoiseFromDict(const py::dict& noise);

// A read-only float64 array of `shape` with a copy of `values`.
py::array_t<double> ArrayOf(const std::vector<double>& values, std::vector<py::ssize_t> shape);

}  // namespace patlab::python

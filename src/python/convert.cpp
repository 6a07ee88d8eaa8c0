// What the bindings share: errors, the signal check, estimator names, noise models, arrays.
#include <Python.h>

#include <algorithm>
#include <utility>

#include "patlab/core/enum_names.h"
#include "patlab/core/error.h"
#include "python/bindings.h"

namespace patlab::python {

void RegisterErrors(py::module_& m) {
  (void)m;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Interrupted&) {
      if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const EnvironmentError& e) {  // before InputError, its base
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

std::function<void(int, int)> SignalCheck() {
  return [](int, int) {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  };
}

std::vector<estimate::Estimator> ParseEstimators(const std::vector<std::string>& names,
                                                 const std::string& field) {
  std::vector<estimate::Estimator> estimators;
  for (const std::string& name : names) {
    const estimate::Estimator e = ParseName(name, estimate::kEstimatorNames, field);
    if (std::find(estimators.begin(), estimators.end(), e) != estimators.end()) {
      throw InputError(field + " lists '" + name + "' twice; expected each estimator once");
    }
    estimators.push_back(e);
  }
  if (estimators.empty()) throw InputError(field + " is empty; expected at least one estimator");
  return estimators;
}

sim::NoiseModel NoiseFromDict(const py::dict& noise) {
  sim::NoiseModel model;
  const std::pair<const char*, double*> fields[] = {
      {"sigma_y_ratio", &model.sigma_y_ratio},
      {"common_sigma_ratio", &model.common_sigma_ratio},
      {"outlier_probability", &model.outlier_probability},
      {"outlier_sigma_ratio", &model.outlier_sigma_ratio},
      {"rotation_jitter_rad", &model.rotation_jitter_rad},
      {"scale_jitter_ppm", &model.scale_jitter_ppm},
      {"correlation_length_mm", &model.correlation_length_mm},
      {"key_shift_x_mm", &model.key_shift_x_mm},
      {"id_shift_x_mm", &model.id_shift_x_mm}};
  for (const auto& [key, value] : noise) {
    const std::string name = py::str(key);
    const auto* field = std::find_if(std::begin(fields), std::end(fields),
                                     [&](const auto& f) { return name == f.first; });
    if (field == std::end(fields)) {
      std::string expected;
      for (const auto& f : fields) expected += std::string(expected.empty() ? "" : ", ") + f.first;
      throw InputError("noise has an unknown key '" + EscapeForMessage(name) +
                       "'; expected one of " + expected);
    }
    *field->second = py::cast<double>(value);
  }
  if (const auto problems = sim::Check(model); !problems.empty()) {
    throw InputError("noise options: " + problems.front().message);
  }
  return model;
}

py::array_t<double> ArrayOf(const std::vector<double>& values, std::vector<py::ssize_t> shape) {
  py::array_t<double> array(shape);
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

}  // namespace patlab::python

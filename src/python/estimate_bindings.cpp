// patlab.estimate and patlab.crlb: the estimators of estimate/estimators.h over many trials at
// once, in parallel with the GIL released, and the bounds of estimate/bounds.h.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"
#include "patlab/estimate/estimators_many.h"
#include "patlab/sim/noise_prediction.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

using Observed = py::array_t<double, py::array::forcecast>;

// estimate()'s methods: the estimators that need the pattern alone (estimate::kAllEstimators, the
// first names of kEstimatorNames). "robust" also needs the noise model's sigma and outlier
// mixture, which estimate() does not take; simulate() runs it.
constexpr EnumNames<estimate::Estimator, estimate::kAllEstimators.size()> kMethodNames = [] {
  EnumNames<estimate::Estimator, estimate::kAllEstimators.size()> names{};
  for (size_t i = 0; i < names.entries.size(); ++i) {
    names.entries[i] = estimate::kEstimatorNames.entries[i];
  }
  return names;
}();
static_assert([] {
  for (size_t i = 0; i < kMethodNames.entries.size(); ++i) {
    if (kMethodNames.entries[i].first != estimate::kAllEstimators[i]) return false;
  }
  return true;
}());

struct EstimateTask {
  const estimate::Model* model;
  estimate::Estimator method;
  estimate::Options options;
};

// One trial: its patches (any strides) into a fixed array, the estimator, the pose.
Pose2 EstimateOne(const EstimateTask& task, const py::detail::unchecked_reference<double, 3>& in,
                  py::ssize_t t, uint8_t* converged) {
  std::array<Vec2, kMaxPatches> v;
  for (int i = 0; i < task.model->num_patches; ++i) v[i] = Vec2(in(t, i, 0), in(t, i, 1));
  switch (task.method) {
    case estimate::Estimator::kFast:
      return estimate::Fast(*task.model, v.data());
    case estimate::Estimator::kLsq:
      return estimate::LeastSquares(*task.model, v.data());
    case estimate::Estimator::kKey:
      return estimate::KeyPatch(*task.model, v.data());
    case estimate::Estimator::kMl:
      break;
    case estimate::Estimator::kRobust:  // not one of kMethodNames
      PATLAB_CHECK(false && "robust is not a method of estimate()");
      return Pose2{};
  }
  estimate::Summary summary;
  const Pose2 start = estimate::Fast(*task.model, v.data());
  const Pose2 pose =
      estimate::MaximumLikelihood(*task.model, v.data(), start, task.options, &summary);
  *converged = summary.termination == estimate::Termination::kConverged ? 1 : 0;
  return pose;
}

// Poses (trials, 3) and, for ml, whether each trial's Newton iteration converged.
// "(10, 4, 2)": an array's shape as numpy prints it.
std::string ShapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    text += (d > 0 ? ", " : "") + std::to_string(a.shape(d));
  }
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// Trials [begin, end) one at a time (EstimateOne): ml, and every method when asked for the
// reference path (tests compare it with EstimateMany's bits).
void EstimateEach(const EstimateTask& task, const py::detail::unchecked_reference<double, 3>& in,
                  py::ssize_t begin, py::ssize_t end, double* out, uint8_t* ok) {
  uint8_t ignored = 0;
  for (py::ssize_t t = begin; t < end; ++t) {
    uint8_t* converged = ok != nullptr ? &ok[t] : &ignored;
    *converged = 1;
    const Pose2 p = EstimateOne(task, in, t, converged);
    out[3 * t] = p.x_mm;
    out[3 * t + 1] = p.y_mm;
    out[3 * t + 2] = p.theta_rad;
  }
}

// Poses (trials, 3) and, for ml, whether each trial's Newton iteration converged. fast, key and
// lsq run estimate::EstimateMany on blocks of trials read in place (vectorised; the bits of the
// one-trial estimators), ml trial by trial; both in parallel over trials with the GIL released.
py::tuple Estimate(const Pattern& pattern, const Observed& observed, const std::string& method,
                   int max_iterations, int threads, bool one_by_one) {
  if (observed.ndim() != 3 || observed.shape(1) != pattern.size() || observed.shape(2) != 2) {
    throw InputError("observed has shape " + ShapeText(observed) + "; expected (trials, " +
                     std::to_string(pattern.size()) +
                     ", 2): the pattern's patches in its order, x and y in mm");
  }
  if (threads < 0) {
    throw InputError("threads is " + std::to_string(threads) +
                     "; expected an integer >= 0 (0: every core)");
  }
  const estimate::Model model = estimate::Model::FromPattern(pattern);
  EstimateTask task{&model, ParseName(method, kMethodNames, "method"), {}};
  task.options.max_iterations = max_iterations;
  estimate::Validate(task.options);
  const py::ssize_t trials = observed.shape(0);
  const bool ml = task.method == estimate::Estimator::kMl;
  const bool many = !one_by_one && estimate::HasManyVersion(task.method);
  py::array_t<double> poses({trials, py::ssize_t{3}});
  std::optional<py::array_t<uint8_t>> converged;
  if (ml) converged.emplace(trials);
  const estimate::PatchArray in{reinterpret_cast<const unsigned char*>(observed.data()),
                                observed.strides(0), observed.strides(1), observed.strides(2)};
  const auto each = observed.unchecked<3>();
  double* out = poses.mutable_data();
  uint8_t* ok = ml ? converged->mutable_data() : nullptr;
  {
    const py::gil_scoped_release nogil;
    const auto run = [&](const tbb::blocked_range<py::ssize_t>& r) {
      if (many) {
        estimate::EstimateMany(model, task.method, in, r.begin(), r.end() - r.begin(),
                               out + 3 * r.begin());
      } else {
        EstimateEach(task, each, r.begin(), r.end(), out, ok);
      }
    };
    const py::ssize_t grain = many ? 16384 : 4096;
    if (threads == 1 || trials <= grain) {
      run(tbb::blocked_range<py::ssize_t>(0, trials));
    } else {
      tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
      arena.execute(
          [&] { tbb::parallel_for(tbb::blocked_range<py::ssize_t>(0, trials, grain), run); });
    }
  }
  if (!ml) return py::make_tuple(poses, py::none());
  return py::make_tuple(poses, converged->attr("astype")("bool"));
}

// The Cramer-Rao bound at patch sigma (mm) under the noise model: per-axis position std (mm) and
// theta std (rad); NaN where the model has none (sim::NoiseCramerRaoBound), as the runner
// reports it.
py::dict Crlb(const Pattern& pattern, double sigma_mm, const py::dict& noise) {
  if (!(std::isfinite(sigma_mm) && sigma_mm >= 0.0)) {
    throw InputError("sigma_mm is " + FormatNumber(sigma_mm) + "; expected a finite number >= 0");
  }
  const sim::NoiseModel model = NoiseFromDict(noise);
  const std::optional<estimate::StdPerSigma> bound =
      sim::NoiseCramerRaoBound(estimate::Model::FromPattern(pattern), model);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  py::dict out;
  out["position_mm"] = bound ? bound->position_per_axis * sigma_mm : nan;
  out["theta_rad"] = bound ? bound->theta * sigma_mm : nan;
  return out;
}

// First-order predicted std of an estimator at patch sigma (mm), independent patch noise; NaN for
// robust (not linear in the noise: its weights depend on the residuals), as the runner reports it.
py::dict Predicted(const Pattern& pattern, const std::string& method, double sigma_mm) {
  const estimate::Estimator estimator = ParseName(method, estimate::kEstimatorNames, "method");
  const estimate::StdPerSigma p =
      estimate::PredictedStd(estimate::Model::FromPattern(pattern), estimator);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const bool linear = estimator != estimate::Estimator::kRobust;
  py::dict out;
  out["position_mm"] = linear ? p.position_per_axis * sigma_mm : nan;
  out["theta_rad"] = linear ? p.theta * sigma_mm : nan;
  return out;
}

}  // namespace

void BindEstimate(py::module_& m) {
  // one_by_one: every method trial by trial through the one-trial estimators (tests compare
  // the vectorised path's bits with it).
  m.def("_estimate", &Estimate, py::arg("pattern"), py::arg("observed").noconvert(false),
        py::arg("method"), py::arg("max_iterations"), py::arg("threads"),
        py::arg("one_by_one") = false);
  // Where the estimator reads `observed`: the array's own buffer when it is float64, whatever
  // its strides (tests/python check that no copy is made).
  m.def("_observed_address",
        [](const Observed& observed) { return reinterpret_cast<uintptr_t>(observed.data()); });
  m.def("_crlb", &Crlb, py::arg("pattern"), py::arg("sigma_mm"), py::arg("noise"));
  m.def("_predicted", &Predicted, py::arg("pattern"), py::arg("method"), py::arg("sigma_mm"));
}

}  // namespace patlab::python

// patlab.stats: the tests and intervals of stats/ (KS, Wilcoxon, the std's chi-square
// interval), as the runner and `patlab stats` compute them, with the GIL released.
#include <optional>
#include <span>

#include "patlab/core/error.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

using Sample = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::span<const double> SpanOf(const Sample& a, const char* what) {
  if (a.ndim() != 1) {
    throw InputError(std::string(what) + " has " + std::to_string(a.ndim()) +
                     " dimensions; expected a 1-dimensional sample");
  }
  return {a.data(), static_cast<size_t>(a.shape(0))};
}

py::dict Ks(const Sample& x, const Sample& y, const std::string& alternative,
            const std::string& method) {
  stats::KsOptions options;
  options.alternative = stats::ParseAlternative(alternative);
  options.method = stats::ParseKsMethod(method);
  const std::span<const double> a = SpanOf(x, "x"), b = SpanOf(y, "y");
  stats::KsResult r;
  {
    const py::gil_scoped_release nogil;
    r = stats::KsTwoSample(a, b, options);
  }
  py::dict out;
  out["statistic"] = r.d;
  out["pvalue"] = r.p_value;
  out["statistic_location"] = r.location;
  out["statistic_sign"] = r.sign;
  out["method"] = std::string(stats::KsMethodName(r.method_used));
  return out;
}

py::dict Wilcoxon(const Sample& x, const std::optional<Sample>& y, const std::string& zero_method,
                  bool correction, const std::string& alternative, const std::string& method) {
  stats::WilcoxonOptions options;
  options.zero_method = stats::ParseZeroMethod(zero_method);
  options.correction = correction;
  options.alternative = stats::ParseAlternative(alternative);
  options.method = stats::ParseWilcoxonMethod(method);
  const std::span<const double> a = SpanOf(x, "x");
  const std::span<const double> b = y ? SpanOf(*y, "y") : std::span<const double>();
  stats::WilcoxonResult r;
  {
    const py::gil_scoped_release nogil;
    r = y ? stats::WilcoxonSignedRank(a, b, options) : stats::WilcoxonSignedRank(a, options);
  }
  py::dict out;
  out["statistic"] = r.statistic;
  out["pvalue"] = r.p_value;
  out["zstatistic"] = r.z;
  out["method"] = std::string(stats::WilcoxonMethodName(r.method_used));
  out["n_zero"] = r.n_zero;
  return out;
}

py::dict StdCi(const Sample& x, double level) {
  const std::span<const double> a = SpanOf(x, "x");
  stats::StdWithCi r;
  {
    const py::gil_scoped_release nogil;
    r = stats::StdWithConfidence(a, level);
  }
  py::dict out;
  out["statistic"] = r.std;
  out["low"] = r.lower;
  out["high"] = r.upper;
  out["confidence_level"] = r.level;
  out["n"] = r.n;
  return out;
}

}  // namespace

void BindStats(py::module_& m) {
  m.def("_ks_2samp", &Ks, py::arg("x"), py::arg("y"), py::arg("alternative"), py::arg("method"));
  m.def("_wilcoxon", &Wilcoxon, py::arg("x"), py::arg("y"), py::arg("zero_method"),
        py::arg("correction"), py::arg("alternative"), py::arg("method"));
  m.def("_chi2_std_ci", &StdCi, py::arg("x"), py::arg("confidence_level"));
}

}  // namespace patlab::python

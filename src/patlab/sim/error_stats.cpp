#include "patlab/sim/error_stats.h"

#include <algorithm>
#include <cmath>

#include "patlab/core/format.h"
#include "patlab/stats/smoothing.h"

namespace patlab::sim {

namespace {

std::vector<double> Pool(const std::vector<ErrorSegment>& segments,
                         const std::vector<double> ErrorSegment::*field) {
  std::vector<double> pooled;
  for (const ErrorSegment& s : segments) {
    pooled.insert(pooled.end(), (s.*field).begin(), (s.*field).end());
  }
  return pooled;
}

// |error| of sample i of a segment on one axis ("x", "y" or "xy").
double AbsError(const ErrorSegment& s, size_t i, const std::string& axis) {
  return axis == "x"   ? std::abs(s.x[i])
         : axis == "y" ? std::abs(s.y[i])
                       : std::hypot(s.x[i], s.y[i]);
}

// The |errors| of a and b at their common (run, frame) keys, in key order.
void PairedAbsErrors(const std::vector<ErrorSegment>& a, const std::vector<ErrorSegment>& b,
                     const std::string& axis, std::vector<double>* va, std::vector<double>* vb) {
  size_t sa = 0, ia = 0, sb = 0, ib = 0;
  while (sa < a.size() && sb < b.size()) {
    if (ia == a[sa].frame.size()) {
      ++sa, ia = 0;
      continue;
    }
    if (ib == b[sb].frame.size()) {
      ++sb, ib = 0;
      continue;
    }
    const auto ka = std::pair(a[sa].run, a[sa].frame[ia]);
    const auto kb = std::pair(b[sb].run, b[sb].frame[ib]);
    if (ka < kb) {
      ++ia;
    } else if (kb < ka) {
      ++ib;
    } else {
      va->push_back(AbsError(a[sa], ia++, axis));
      vb->push_back(AbsError(b[sb], ib++, axis));
    }
  }
}

double UpperMedian(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

ErrorSummary SummariseErrors(const std::vector<ErrorSegment>& segments, int lag) {
  ErrorSummary s;
  const std::vector<double> x = Pool(segments, &ErrorSegment::x);
  const std::vector<double> y = Pool(segments, &ErrorSegment::y);
  s.x = stats::StdWithConfidence(x);
  s.y = stats::StdWithConfidence(y);
  s.mean_x = stats::Mean(x);
  s.mean_y = stats::Mean(y);
  int counted = 0;
  for (const ErrorSegment& g : segments) {
    if (g.x.size() < static_cast<size_t>(lag) + 2) continue;
    s.lag_x += stats::Autocorrelation(g.x, static_cast<size_t>(lag));
    s.lag_y += stats::Autocorrelation(g.y, static_cast<size_t>(lag));
    ++counted;
  }
  if (counted > 0) {
    s.lag_x /= counted;
    s.lag_y /= counted;
  }
  const std::vector<double> theta = Pool(segments, &ErrorSegment::theta);
  if (!theta.empty()) {
    s.has_theta = true;
    s.theta = stats::StdWithConfidence(theta);
  }
  return s;
}

std::vector<PairedTest> PairedAbsErrorTests(
    const std::string& error, const std::vector<std::string>& names,
    const std::vector<const std::vector<ErrorSegment>*>& subjects) {
  std::vector<PairedTest> tests;
  stats::WilcoxonOptions options;
  options.method = stats::WilcoxonMethod::kApprox;
  for (const std::string axis : {"x", "y", "xy"}) {
    for (size_t a = 0; a < subjects.size(); ++a) {
      for (size_t b = a + 1; b < subjects.size(); ++b) {
        std::vector<double> va, vb;
        PairedAbsErrors(*subjects[a], *subjects[b], axis, &va, &vb);
        if (va.empty()) continue;
        tests.push_back({error, axis, names[a], names[b], UpperMedian(va), UpperMedian(vb),
                         stats::WilcoxonSignedRank(va, vb, options)});
      }
    }
  }
  return tests;
}

std::string PairedTestsCsv(const std::vector<PairedTest>& tests) {
  std::string csv =
      "error,axis,a,b,n,median_abs_a_mm,median_abs_b_mm,r_plus,r_minus,z,p_value,smaller\n";
  for (const PairedTest& t : tests) {
    const auto& w = t.result;
    // R+ > R-: |a| - |b| tends to be positive, so b has the smaller errors.
    const std::string smaller = w.r_plus > w.r_minus ? t.b : w.r_plus < w.r_minus ? t.a : "";
    csv += t.error + "," + t.axis + "," + t.a + "," + t.b + "," + std::to_string(w.n) + "," +
           FormatFixed(t.median_abs_a_mm, 4) + "," + FormatFixed(t.median_abs_b_mm, 4) + "," +
           FormatSignificant(w.r_plus, 12) + "," + FormatSignificant(w.r_minus, 12) + "," +
           FormatFixed(w.z, 3) + "," + FormatSignificant(w.p_value, 3) + "," + smaller + "\n";
  }
  return csv;
}

}  // namespace patlab::sim

#include "patlab/sim/error_stats.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "patlab/core/format.h"
#include "patlab/stats/smoothing.h"

namespace patlab::sim {

namespace {

std::vector<double> Pool(const std::vector<ErrorSegment>& segments,
                         const std::vector<double> ErrorSegment::*field) {
  std::vector<double> pooled;
  size_t n = 0;
  for (const ErrorSegment& s : segments) n += (s.*field).size();
  pooled.reserve(n);
  for (const ErrorSegment& s : segments) {
    pooled.insert(pooled.end(), (s.*field).begin(), (s.*field).end());
  }
  return pooled;
}

// One subject's samples flattened in (run, frame) order, with their |error| on one axis.
struct AbsErrors {
  std::vector<std::pair<int, int64_t>> key;  // (run, frame)
  std::vector<double> abs;
};

enum class Axis { kX, kY, kXy };

// |error| of every sample on `axis` ("x", "y", "xy" = hypot), in segment order.
AbsErrors FlattenAbsErrors(const std::vector<ErrorSegment>& segments, Axis axis) {
  AbsErrors out;
  size_t n = 0;
  for (const ErrorSegment& s : segments) n += s.frame.size();
  out.key.reserve(n);
  out.abs.reserve(n);
  for (const ErrorSegment& s : segments) {
    for (size_t i = 0; i < s.frame.size(); ++i) {
      out.key.emplace_back(s.run, s.frame[i]);
      out.abs.push_back(axis == Axis::kX   ? std::abs(s.x[i])
                        : axis == Axis::kY ? std::abs(s.y[i])
                                           : std::hypot(s.x[i], s.y[i]));
    }
  }
  return out;
}

// The |errors| of a and b at their common (run, frame) keys, in key order (segments are in run
// order, frames increasing within a run, so a merge finds them).
void PairedAbsErrors(const AbsErrors& a, const AbsErrors& b, std::vector<double>* va,
                     std::vector<double>* vb) {
  size_t ia = 0, ib = 0;
  va->reserve(std::min(a.abs.size(), b.abs.size()));
  vb->reserve(std::min(a.abs.size(), b.abs.size()));
  while (ia < a.key.size() && ib < b.key.size()) {
    if (a.key[ia] < b.key[ib]) {
      ++ia;
    } else if (b.key[ib] < a.key[ia]) {
      ++ib;
    } else {
      va->push_back(a.abs[ia++]);
      vb->push_back(b.abs[ib++]);
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
  for (const auto& [axis, name] :
       {std::pair(Axis::kX, "x"), std::pair(Axis::kY, "y"), std::pair(Axis::kXy, "xy")}) {
    // Each subject's |errors| once; and its median once when a pair uses all of its samples (the
    // usual case: subjects seen in the same frames), instead of once per pair.
    std::vector<AbsErrors> flat;
    flat.reserve(subjects.size());
    for (const auto* segments : subjects) flat.push_back(FlattenAbsErrors(*segments, axis));
    std::vector<std::optional<double>> whole_median(subjects.size());
    const auto median = [&](size_t k, const std::vector<double>& v) {
      if (v.size() != flat[k].abs.size()) return UpperMedian(v);
      if (!whole_median[k]) whole_median[k] = UpperMedian(v);
      return *whole_median[k];
    };
    for (size_t a = 0; a < subjects.size(); ++a) {
      for (size_t b = a + 1; b < subjects.size(); ++b) {
        std::vector<double> va, vb;
        PairedAbsErrors(flat[a], flat[b], &va, &vb);
        if (va.empty()) continue;
        const stats::WilcoxonResult result = stats::WilcoxonSignedRank(va, vb, options);
        tests.push_back({error, name, names[a], names[b], median(a, va), median(b, vb), result});
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

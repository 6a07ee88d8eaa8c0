#include "patlab/stats/error_stats.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <utility>

#include "patlab/core/format.h"
#include "patlab/io/csv.h"
#include "patlab/stats/smoothing.h"

namespace patlab::stats {

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

enum class Axis { kX, kY, kXy };

// |error| of every sample on `axis` ("x", "y", "xy" = hypot), in segment order.
std::vector<double> FlattenAbsErrors(const std::vector<ErrorSegment>& segments, Axis axis) {
  size_t n = 0;
  for (const ErrorSegment& s : segments) n += s.frame.size();
  std::vector<double> out(n);
  size_t k = 0;
  for (const ErrorSegment& s : segments) {
    for (size_t i = 0; i < s.frame.size(); ++i, ++k) {
      out[k] = axis == Axis::kX   ? std::abs(s.x[i])
               : axis == Axis::kY ? std::abs(s.y[i])
                                  : std::hypot(s.x[i], s.y[i]);
    }
  }
  return out;
}

// True when a and b hold the same (run, frame) keys in the same segments: then sample i of one
// pairs with sample i of the other (the usual case: subjects seen in the same frames).
bool SameKeys(const std::vector<ErrorSegment>& a, const std::vector<ErrorSegment>& b) {
  if (a.size() != b.size()) return false;
  for (size_t g = 0; g < a.size(); ++g) {
    if (a[g].run != b[g].run || a[g].frame != b[g].frame) return false;
  }
  return true;
}

// The differences |a| - |b| at the common (run, frame) keys, in key order (segments are in run
// order, frames increasing within a run, so a merge finds them), and the paired |errors|.
void PairedAbsErrors(const std::vector<ErrorSegment>& sa, const std::vector<double>& a,
                     const std::vector<ErrorSegment>& sb, const std::vector<double>& b,
                     std::vector<double>* va, std::vector<double>* vb) {
  const auto keys = [](const std::vector<ErrorSegment>& segments) {
    std::vector<std::pair<int, int64_t>> key;
    for (const ErrorSegment& s : segments) {
      for (const int64_t f : s.frame) key.emplace_back(s.run, f);
    }
    return key;
  };
  const std::vector<std::pair<int, int64_t>> ka = keys(sa), kb = keys(sb);
  size_t ia = 0, ib = 0;
  while (ia < ka.size() && ib < kb.size()) {
    if (ka[ia] < kb[ib]) {
      ++ia;
    } else if (kb[ib] < ka[ia]) {
      ++ib;
    } else {
      va->push_back(a[ia++]);
      vb->push_back(b[ib++]);
    }
  }
}

double UpperMedian(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

namespace {

// The effective size of one axis of `segments` and the interval of `iid.std` on (n - 1) / tau dof.
stats::StdWithCi Effective(const std::vector<ErrorSegment>& segments,
                           const std::vector<double> ErrorSegment::*field,
                           const stats::StdWithCi& iid, int min_lags, stats::EffectiveSize* size) {
  std::vector<std::span<const double>> spans;
  spans.reserve(segments.size());
  for (const ErrorSegment& s : segments) spans.emplace_back(s.*field);
  *size = stats::VarianceEffectiveSize(spans, 1000, min_lags);
  if (size->tau == 1.0) return iid;  // white: the same numbers as the iid interval
  stats::StdWithCi ci = stats::StdConfidenceInterval(
      iid.std, (static_cast<double>(iid.n) - 1.0) / size->tau, iid.level);
  ci.n = iid.n;
  return ci;
}

}  // namespace

ErrorSummary SummariseErrors(const std::vector<ErrorSegment>& segments, int lag, int min_lags) {
  ErrorSummary s;
  const std::vector<double> x = Pool(segments, &ErrorSegment::x);
  const std::vector<double> y = Pool(segments, &ErrorSegment::y);
  s.x_iid = stats::StdWithConfidence(x);
  s.y_iid = stats::StdWithConfidence(y);
  s.x = Effective(segments, &ErrorSegment::x, s.x_iid, min_lags, &s.size_x);
  s.y = Effective(segments, &ErrorSegment::y, s.y_iid, min_lags, &s.size_y);
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
    s.theta_iid = stats::StdWithConfidence(theta);
    s.theta = Effective(segments, &ErrorSegment::theta, s.theta_iid, min_lags, &s.size_theta);
  }
  return s;
}

std::string IidIntervalWarning(const std::string& what, const stats::EffectiveSize& size) {
  if (size.tau < kIidWarningTau) return "";
  return "warning: " + what + ": lag-1 autocorrelation " + FormatFixed(size.lag1, 3) +
         ", variance inflation tau " + FormatFixed(size.tau, 2) +
         ": the iid 95% interval (the *_iid_lo/*_iid_hi columns) is " +
         FormatFixed(std::sqrt(size.tau), 2) +
         "x too narrow; the *_lo/*_hi columns use (n - 1) / tau degrees of freedom";
}

std::vector<PairedTest> PairedAbsErrorTests(
    const std::string& error, const std::vector<std::string>& names,
    const std::vector<const std::vector<ErrorSegment>*>& subjects) {
  std::vector<PairedTest> tests;
  std::vector<double> d;
  stats::WilcoxonOptions options;
  options.method = stats::WilcoxonMethod::kApprox;
  for (const auto& [axis, name] :
       {std::pair(Axis::kX, "x"), std::pair(Axis::kY, "y"), std::pair(Axis::kXy, "xy")}) {
    // Each subject's |errors| once; and its median once when a pair uses all of its samples (the
    // usual case: subjects seen in the same frames), instead of once per pair.
    std::vector<std::vector<double>> flat;
    flat.reserve(subjects.size());
    for (const auto* segments : subjects) flat.push_back(FlattenAbsErrors(*segments, axis));
    std::vector<std::optional<double>> whole_median(subjects.size());
    const auto median = [&](size_t k, const std::vector<double>& v) {
      if (&v != &flat[k]) return UpperMedian(v);
      if (!whole_median[k]) whole_median[k] = UpperMedian(v);
      return *whole_median[k];
    };
    for (size_t a = 0; a < subjects.size(); ++a) {
      for (size_t b = a + 1; b < subjects.size(); ++b) {
        std::vector<double> pa, pb;
        const bool same = SameKeys(*subjects[a], *subjects[b]);
        if (!same) PairedAbsErrors(*subjects[a], flat[a], *subjects[b], flat[b], &pa, &pb);
        const std::vector<double>& va = same ? flat[a] : pa;
        const std::vector<double>& vb = same ? flat[b] : pb;
        if (va.empty()) continue;
        // |a| - |b| in a reused buffer, ranked in place (as WilcoxonSignedRank(va, vb) does on
        // its copy; the |errors| are finite).
        if (d.size() < va.size()) d.resize(va.size());
        for (size_t i = 0; i < va.size(); ++i) d[i] = va[i] - vb[i];
        const stats::WilcoxonResult result =
            stats::WilcoxonSignedRankInPlace(std::span<double>(d.data(), va.size()), options);
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
    io::CsvWriter(&csv)
        .Cells({t.error, t.axis, t.a, t.b})
        .Cell(static_cast<int64_t>(w.n))
        .Cells({FormatFixed(t.median_abs_a_mm, 4), FormatFixed(t.median_abs_b_mm, 4),
                FormatSignificant(w.r_plus, 12), FormatSignificant(w.r_minus, 12),
                FormatFixed(w.z, 3), FormatSignificant(w.p_value, 3), smaller})
        .EndRow();
  }
  return csv;
}

}  // namespace patlab::stats

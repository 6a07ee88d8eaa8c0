#include "patlab/analysis/analyze.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "patlab/analysis/analyze_internal.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/geometry.h"

namespace patlab::analysis {

namespace {

using detail::Cat;
using detail::Quoted;

// theta continued across the +-pi cut so that smoothing sees no jump of 2 pi.
std::vector<double> Unwrapped(std::span<const double> theta) {
  std::vector<double> out(theta.begin(), theta.end());
  for (size_t i = 1; i < out.size(); ++i) out[i] = out[i - 1] + WrapAngle(theta[i] - theta[i - 1]);
  return out;
}

// Where a segment's kept samples are and how its errors are rotated.
struct SegmentFrame {
  size_t begin = 0, end = 0;  // kept samples [begin, end) of the track
  double cos_h = 1.0, sin_h = 0.0;
};

void AppendRotated(const SegmentFrame& f, double ex, double ey, stats::ErrorSegment* s) {
  // The error in the frame rotated by the heading h: R(-h) (ex, ey).
  s->x.push_back(f.cos_h * ex + f.sin_h * ey);
  s->y.push_back(-f.sin_h * ex + f.cos_h * ey);
}

// The trend of a segment's samples: smoothed, the least-squares line against the sample index,
// or the mean (AnalyzeOptions::detrend).
std::vector<double> Trend(std::span<const double> x, const AnalyzeOptions& o) {
  if (o.detrend == Detrend::kSmooth) return stats::GaussianSmooth(x, o.smoothing);
  const auto n = static_cast<double>(x.size());
  double mean = 0.0;
  for (double v : x) mean += v;
  mean /= n;
  double slope = 0.0;
  if (o.detrend == Detrend::kLinear) {
    const double centre = (n - 1.0) / 2.0;
    double sxy = 0.0, sxx = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
      const double u = static_cast<double>(i) - centre;
      sxy += u * (x[i] - mean);
      sxx += u * u;
    }
    slope = sxy / sxx;
  }
  std::vector<double> trend(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    trend[i] = mean + slope * (static_cast<double>(i) - (n - 1.0) / 2.0);
  }
  return trend;
}

// The residuals of samples [lo, hi) of a track (one gap-free segment), kept part only.
stats::ErrorSegment SegmentResiduals(const MeasuredTrack& t, size_t lo, size_t hi, int run,
                                     const AnalyzeOptions& o, int radius, SegmentFrame* f) {
  const auto span = [&](const std::vector<double>& v) {
    return std::span<const double>(v.data() + lo, hi - lo);
  };
  const std::vector<double> sx = Trend(span(t.x), o);
  const std::vector<double> sy = Trend(span(t.y), o);
  std::vector<double> rt;
  if (!t.theta.empty()) {
    rt = Unwrapped(span(t.theta));
    if (o.detrend == Detrend::kSmooth) {
      rt = stats::SmoothingResiduals(rt, o.smoothing);
    } else {
      const std::vector<double> trend = Trend(rt, o);
      for (size_t i = 0; i < rt.size(); ++i) rt[i] -= trend[i];
    }
  }
  const auto r = static_cast<size_t>(radius);
  f->begin = lo + r;
  f->end = hi - r;
  if (o.along_travel) {
    const double h = std::atan2(sy[hi - lo - r - 1] - sy[r], sx[hi - lo - r - 1] - sx[r]);
    f->cos_h = std::cos(h);
    f->sin_h = std::sin(h);
  }
  stats::ErrorSegment s;
  s.run = run;
  s.frame.reserve(f->end - f->begin);
  s.x.reserve(f->end - f->begin);
  s.y.reserve(f->end - f->begin);
  if (!rt.empty()) s.theta.reserve(f->end - f->begin);
  for (size_t i = f->begin; i < f->end; ++i) {
    s.frame.push_back(t.frame[i]);
    AppendRotated(*f, t.x[i] - sx[i - lo], t.y[i] - sy[i - lo], &s);
    if (!rt.empty()) s.theta.push_back(WrapAngle(rt[i - lo]));
  }
  return s;
}

// The true errors of the kept samples of a segment: sample - truth, rotated like the residuals.
stats::ErrorSegment SegmentTruth(const MeasuredTrack& t, const MeasuredTrack& truth,
                                 const SegmentFrame& f, int run) {
  stats::ErrorSegment s;
  s.run = run;
  for (size_t i = f.begin; i < f.end; ++i) {
    const auto it = std::lower_bound(truth.frame.begin(), truth.frame.end(), t.frame[i]);
    if (it == truth.frame.end() || *it != t.frame[i]) {
      throw InputError(
          FileLoc{truth.file, truth.first_line},
          Cat("no truth for subject ", Quoted(t.subject), " run ", Quoted(t.run), " frame ",
              std::to_string(t.frame[i]), "; expected the truth of every analysed frame"));
    }
    const auto j = static_cast<size_t>(it - truth.frame.begin());
    s.frame.push_back(t.frame[i]);
    AppendRotated(f, t.x[i] - truth.x[j], t.y[i] - truth.y[j], &s);
    if (!t.theta.empty() && !truth.theta.empty()) {
      s.theta.push_back(WrapAngle(t.theta[i] - truth.theta[j]));
    }
  }
  return s;
}

// The truth of track t: the truth track of its subject and run, or else the only one of its subject
// (a truth file without a run column names its run after itself).
const MeasuredTrack& FindTruth(const std::vector<MeasuredTrack>& truth, const MeasuredTrack& t) {
  const MeasuredTrack* only = nullptr;
  int of_subject = 0;
  for (const MeasuredTrack& u : truth) {
    if (u.subject != t.subject) continue;
    if (u.run == t.run) return u;
    only = &u;
    ++of_subject;
  }
  if (of_subject == 1) return *only;
  throw InputError(FileLoc{t.file, t.first_line},
                   Cat("subject ", Quoted(t.subject), " run ", Quoted(t.run),
                       " is not in the truth file; expected the truth of every subject and run"));
}

// Splits one track at its gaps and adds the analysed segments to `a`; returns its longest segment.
size_t AnalyseTrack(const MeasuredTrack& t, int run, const AnalyzeOptions& o, int radius,
                    const std::vector<MeasuredTrack>* truth, SubjectAnalysis* a) {
  a->samples += t.frame.size();
  size_t longest = 0;
  size_t lo = 0;
  while (lo < t.frame.size()) {
    size_t hi = lo + 1;
    while (hi < t.frame.size() && t.frame[hi] == t.frame[hi - 1] + 1) ++hi;
    longest = std::max(longest, hi - lo);
    if (hi - lo < static_cast<size_t>(2 * radius + 1)) {
      ++a->skipped_segments;
      a->skipped_samples += hi - lo;
    } else {
      SegmentFrame f;
      a->est_errors.push_back(SegmentResiduals(t, lo, hi, run, o, radius, &f));
      if (truth) a->true_errors.push_back(SegmentTruth(t, FindTruth(*truth, t), f, run));
      ++a->segments;
    }
    lo = hi;
  }
  return longest;
}

void ScaleStd(stats::StdWithCi* s, double factor) {
  s->std /= factor;
  s->lower /= factor;
  s->upper /= factor;
}

// The summaries of one subject whose tracks (indices into `tracks`) are in run order.
// With `release` (the same vector as `tracks`), each track's samples are freed once analysed, so
// that the memory of the samples is reused for the errors.
SubjectAnalysis AnalyseSubject(const std::vector<MeasuredTrack>& tracks,
                               const std::vector<std::pair<int, size_t>>& runs_and_tracks,
                               const AnalyzeReport& report, const std::vector<MeasuredTrack>* truth,
                               std::vector<MeasuredTrack>* release) {
  SubjectAnalysis a;
  const MeasuredTrack& first = tracks[runs_and_tracks.front().second];
  a.subject = first.subject;
  size_t longest = 0;
  for (const auto& [run, k] : runs_and_tracks) {
    longest =
        std::max(longest, AnalyseTrack(tracks[k], run, report.options, report.radius, truth, &a));
    if (release) {
      MeasuredTrack& t = (*release)[k];
      std::vector<int64_t>().swap(t.frame);
      for (std::vector<double>* v : {&t.x, &t.y, &t.theta}) std::vector<double>().swap(*v);
    }
  }
  if (a.segments == 0) {
    const std::string why =
        report.options.detrend == Detrend::kSmooth
            ? Cat("2 x ", std::to_string(report.radius), " + 1 for smoothing with sigma = ",
                  FormatSignificant(report.options.smoothing.sigma_samples, 6), " samples")
            : Cat(std::to_string(report.min_segment), " for detrend ",
                  std::string(NameOf(report.options.detrend, kDetrendNames)));
    throw InputError(FileLoc{first.file, first.first_line},
                     Cat("subject ", Quoted(a.subject), " has no run of ",
                         std::to_string(report.min_segment), " consecutive frames (longest: ",
                         std::to_string(longest), "); expected at least ", why));
  }
  a.est = stats::SummariseErrors(a.est_errors, report.options.lag, 2 * report.radius);
  if (report.options.correct_bias) {
    for (stats::StdWithCi* s : {&a.est.x, &a.est.y, &a.est.x_iid, &a.est.y_iid}) {
      ScaleStd(s, report.residual_factor);
    }
    if (a.est.has_theta) {
      ScaleStd(&a.est.theta, report.residual_factor);
      ScaleStd(&a.est.theta_iid, report.residual_factor);
    }
  }
  if (truth) {
    a.has_truth = true;
    a.truth = stats::SummariseErrors(a.true_errors, report.options.lag);
  }
  return a;
}

// A warning per std of the subject whose iid interval is off (IidIntervalWarning).
void AddWarnings(const SubjectAnalysis& a, std::vector<std::string>* warnings) {
  const auto add = [&](const char* which, const stats::ErrorSummary& e) {
    const std::pair<const char*, const stats::EffectiveSize*> axes[] = {
        {"x", &e.size_x}, {"y", &e.size_y}, {"theta", &e.size_theta}};
    for (const auto& [axis, size] : axes) {
      if (std::string(axis) == "theta" && !e.has_theta) continue;
      const std::string w = stats::IidIntervalWarning(
          Cat("subject ", Quoted(a.subject), ", ", which, " ", axis), *size);
      if (!w.empty()) warnings->push_back(w);
    }
  };
  add("est", a.est);
  if (a.has_truth) add("true", a.truth);
}

}  // namespace

std::vector<OptionsProblem> Check(const AnalyzeOptions& o) {
  std::vector<OptionsProblem> problems = stats::Check(o.smoothing);
  OptionsChecker check;
  check.Positive("sigma_samples", o.smoothing.sigma_samples, "samples")
      .IntegerInRange("lag", o.lag, 1, 1000000);
  for (OptionsProblem& p : check.Take()) problems.push_back(std::move(p));
  if (o.along_travel && o.detrend == Detrend::kNone) {
    problems.push_back({"along_travel",
                        "along_travel is true with detrend \"none\"; expected detrend \"smooth\" "
                        "or \"linear\" (a mean has no direction of travel)"});
  }
  return problems;
}

void Validate(const AnalyzeOptions& options) { ThrowFirstProblem(Check(options)); }

namespace {

AnalyzeReport Analyze(const std::vector<MeasuredTrack>& tracks, const AnalyzeOptions& options,
                      const std::vector<MeasuredTrack>* truth,
                      std::vector<MeasuredTrack>* release) {
  Validate(options);
  AnalyzeReport report;
  report.options = options;
  if (options.detrend == Detrend::kSmooth) {
    report.radius = static_cast<int>(stats::GaussianKernel(options.smoothing).size()) - 1;
    report.min_segment = 2 * report.radius + 1;
    report.residual_factor = stats::ResidualStdFactor(options.smoothing);
    report.white_noise_lag =
        stats::ResidualAutocorrelation(options.smoothing, static_cast<size_t>(options.lag));
  } else {
    report.min_segment = options.detrend == Detrend::kLinear ? 3 : 2;
    report.residual_factor = 1.0;
  }
  // Runs and subjects in order of first appearance; each subject's tracks in run order.
  std::map<std::string, int> run_index;
  std::map<std::string, size_t> subject_index;
  std::vector<std::vector<std::pair<int, size_t>>> by_subject;
  for (size_t k = 0; k < tracks.size(); ++k) {
    const auto [r, new_run] =
        run_index.emplace(tracks[k].run, static_cast<int>(report.runs.size()));
    if (new_run) report.runs.push_back(tracks[k].run);
    const auto [s, new_subject] = subject_index.emplace(tracks[k].subject, by_subject.size());
    if (new_subject) by_subject.emplace_back();
    by_subject[s->second].emplace_back(r->second, k);
  }
  for (auto& runs_and_tracks : by_subject) {
    if (options.progress && !report.subjects.empty()) {
      options.progress(static_cast<int>(report.subjects.size()),
                       static_cast<int>(by_subject.size()));
    }
    std::sort(runs_and_tracks.begin(), runs_and_tracks.end());
    for (size_t i = 1; i < runs_and_tracks.size(); ++i) {
      if (runs_and_tracks[i].first != runs_and_tracks[i - 1].first) continue;
      const MeasuredTrack& t = tracks[runs_and_tracks[i].second];
      throw InputError(FileLoc{t.file, t.first_line},
                       Cat("subject ", Quoted(t.subject), " run ", Quoted(t.run), " is also in ",
                           tracks[runs_and_tracks[i - 1].second].file,
                           "; expected each subject and run in one file"));
    }
    report.subjects.push_back(AnalyseSubject(tracks, runs_and_tracks, report, truth, release));
    AddWarnings(report.subjects.back(), &report.warnings);
  }
  if (options.progress) {
    options.progress(static_cast<int>(report.subjects.size()), static_cast<int>(by_subject.size()));
  }
  std::vector<std::string> names;
  std::vector<const std::vector<stats::ErrorSegment>*> est, true_errors;
  for (const SubjectAnalysis& a : report.subjects) {
    names.push_back(a.subject);
    est.push_back(&a.est_errors);
    true_errors.push_back(&a.true_errors);
  }
  report.tests = stats::PairedAbsErrorTests("est", names, est);
  if (truth) {
    const std::vector<stats::PairedTest> t = stats::PairedAbsErrorTests("true", names, true_errors);
    report.tests.insert(report.tests.end(), t.begin(), t.end());
  }
  return report;
}

}  // namespace

AnalyzeReport AnalyzeTracks(const std::vector<MeasuredTrack>& tracks, const AnalyzeOptions& options,
                            const std::vector<MeasuredTrack>* truth) {
  return Analyze(tracks, options, truth, nullptr);
}

AnalyzeReport AnalyzeTracks(std::vector<MeasuredTrack>&& tracks, const AnalyzeOptions& options,
                            const std::vector<MeasuredTrack>* truth) {
  return Analyze(tracks, options, truth, &tracks);
}

}  // namespace patlab::analysis

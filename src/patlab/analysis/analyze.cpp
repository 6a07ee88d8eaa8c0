#include "patlab/analysis/analyze.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "patlab/analysis/analyze_internal.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/geometry.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"

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

// The residuals of samples [lo, hi) of a track (one gap-free segment), kept part only.
stats::ErrorSegment SegmentResiduals(const MeasuredTrack& t, size_t lo, size_t hi, int run,
                                     const AnalyzeOptions& o, int radius, SegmentFrame* f) {
  const auto span = [&](const std::vector<double>& v) {
    return std::span<const double>(v.data() + lo, hi - lo);
  };
  const std::vector<double> sx = stats::GaussianSmooth(span(t.x), o.smoothing);
  const std::vector<double> sy = stats::GaussianSmooth(span(t.y), o.smoothing);
  std::vector<double> rt;
  if (!t.theta.empty()) rt = stats::SmoothingResiduals(Unwrapped(span(t.theta)), o.smoothing);
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
    throw InputError(
        FileLoc{first.file, first.first_line},
        Cat("subject ", Quoted(a.subject), " has no run of ", std::to_string(report.min_segment),
            " consecutive frames (longest: ", std::to_string(longest), "); expected at least 2 x ",
            std::to_string(report.radius), " + 1 for smoothing with sigma = ",
            FormatSignificant(report.options.smoothing.sigma_samples, 6), " samples"));
  }
  a.est = stats::SummariseErrors(a.est_errors, report.options.lag);
  if (report.options.correct_bias) {
    ScaleStd(&a.est.x, report.residual_factor);
    ScaleStd(&a.est.y, report.residual_factor);
    if (a.est.has_theta) ScaleStd(&a.est.theta, report.residual_factor);
  }
  if (truth) {
    a.has_truth = true;
    a.truth = stats::SummariseErrors(a.true_errors, report.options.lag);
  }
  return a;
}

std::string Fixed(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  return {buf, r.ptr};
}

nlohmann::json StdJson(const stats::StdWithCi& s) {
  return {{"std", s.std}, {"lower", s.lower}, {"upper", s.upper}, {"n", s.n}};
}

nlohmann::json SummaryJson(const stats::ErrorSummary& s) {
  nlohmann::json j = {{"x", StdJson(s.x)},  {"y", StdJson(s.y)}, {"mean_x", s.mean_x},
                      {"mean_y", s.mean_y}, {"lag_x", s.lag_x},  {"lag_y", s.lag_y}};
  if (s.has_theta) j["theta"] = StdJson(s.theta);
  return j;
}

}  // namespace

std::vector<OptionsProblem> Check(const AnalyzeOptions& o) {
  std::vector<OptionsProblem> problems = stats::Check(o.smoothing);
  OptionsChecker check;
  check.Positive("sigma_samples", o.smoothing.sigma_samples, "samples")
      .IntegerInRange("lag", o.lag, 1, 1000000);
  for (OptionsProblem& p : check.Take()) problems.push_back(std::move(p));
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
  report.radius = static_cast<int>(stats::GaussianKernel(options.smoothing).size()) - 1;
  report.min_segment = 2 * report.radius + 1;
  report.residual_factor = stats::ResidualStdFactor(options.smoothing);
  report.white_noise_lag =
      stats::ResidualAutocorrelation(options.smoothing, static_cast<size_t>(options.lag));
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

std::string AnalyzeTableCsv(const AnalyzeReport& report) {
  const std::string lag = std::to_string(report.options.lag);
  std::string csv =
      "subject,n,samples,segments,skipped_segments,skipped_samples,sx_mm,sx_lo,sx_hi,"
      "sy_mm,sy_lo,sy_hi,stheta_rad,stheta_lo,stheta_hi,lag" +
      lag + "_x,lag" + lag +
      "_y,true_sx_mm,true_sx_lo,true_sx_hi,true_sy_mm,true_sy_lo,true_sy_hi,"
      "true_stheta_rad,true_stheta_lo,true_stheta_hi,true_mean_x_mm,true_mean_y_mm\n";
  io::CsvWriter w(&csv);
  auto ci = [&w](const stats::StdWithCi& s, bool present, int decimals) {
    if (!present) {
      w.Cells({"", "", ""});
      return;
    }
    w.Cells({Fixed(s.std, decimals), Fixed(s.lower, decimals), Fixed(s.upper, decimals)});
  };
  for (const SubjectAnalysis& a : report.subjects) {
    const stats::ErrorSummary& e = a.est;
    const stats::ErrorSummary& t = a.truth;
    const bool tt = a.has_truth && t.has_theta;
    w.Cell(a.subject);
    w.Cell(static_cast<int64_t>(e.x.n)).Cell(static_cast<int64_t>(a.samples));
    w.Cell(static_cast<int64_t>(a.segments)).Cell(static_cast<int64_t>(a.skipped_segments));
    w.Cell(static_cast<int64_t>(a.skipped_samples));
    ci(e.x, true, 4);
    ci(e.y, true, 4);
    ci(e.theta, e.has_theta, 6);
    w.Cells({Fixed(e.lag_x, 3), Fixed(e.lag_y, 3)});
    ci(t.x, a.has_truth, 4);
    ci(t.y, a.has_truth, 4);
    ci(t.theta, tt, 6);
    w.Cells({a.has_truth ? Fixed(t.mean_x, 4) : "", a.has_truth ? Fixed(t.mean_y, 4) : ""});
    w.EndRow();
  }
  return csv;
}

namespace {

// The errors CSV formatted straight into a buffer of about 256 kB that is handed to the sink
// whenever the next row might not fit (no per-row string appends, no whole-file string).
class ErrorsWriter {
 public:
  // A frame (at most 20 characters) and up to six fixed-point cells of at most
  // 1 + 1 + 309 + 1 + 6 characters each (comma, sign, |v| up to DBL_MAX, point, decimals), '\n'.
  static constexpr size_t kMaxNumbers = 20 + 6 * 318 + 1;
  static constexpr size_t kBlock = size_t{1} << 18;

  explicit ErrorsWriter(const std::function<void(std::string_view)>& sink)
      : sink_(sink), buffer_(kBlock + kMaxNumbers) {}

  void Text(std::string_view text) {
    Room(text.size());
    std::memcpy(buffer_.data() + used_, text.data(), text.size());
    used_ += text.size();
  }
  // One row: prefix, frame, the estimated errors and (when given) the true ones.
  void Row(std::string_view prefix, int64_t frame, const stats::ErrorSegment& est, size_t i,
           const stats::ErrorSegment* truth) {
    Room(prefix.size() + kMaxNumbers);
    char* p = buffer_.data() + used_;
    std::memcpy(p, prefix.data(), prefix.size());
    p += prefix.size();
    char* const end = buffer_.data() + buffer_.size();
    p = std::to_chars(p, end, frame).ptr;
    p = Errors(p, end, est, i);
    if (truth) p = Errors(p, end, *truth, i);
    *p++ = '\n';
    used_ = static_cast<size_t>(p - buffer_.data());
  }
  void Flush() {
    if (used_ > 0) sink_(std::string_view(buffer_.data(), used_));
    used_ = 0;
  }

 private:
  // Makes room for `size` more characters: flushes when the block is full, grows the buffer
  // for a row longer than a block (a subject or run name of hundreds of kB).
  void Room(size_t size) {
    if (used_ + size <= buffer_.size() && used_ <= kBlock) return;
    Flush();
    if (size > buffer_.size()) buffer_.resize(size);
  }
  // ",x,y,theta" of sample i with 4, 4 and 6 decimals, a cell empty when its column is absent.
  static char* Errors(char* p, char* end, const stats::ErrorSegment& e, size_t i) {
    for (const auto& [v, d] : {std::pair(&e.x, 4), std::pair(&e.y, 4), std::pair(&e.theta, 6)}) {
      *p++ = ',';
      if (!v->empty()) p = std::to_chars(p, end, (*v)[i], std::chars_format::fixed, d).ptr;
    }
    return p;
  }

  const std::function<void(std::string_view)>& sink_;
  std::vector<char> buffer_;
  size_t used_ = 0;
};

}  // namespace

void WriteAnalyzeErrorsCsv(const AnalyzeReport& report,
                           const std::function<void(std::string_view)>& sink) {
  const bool truth = !report.subjects.empty() && report.subjects.front().has_truth;
  ErrorsWriter out(sink);
  out.Text("subject,run,frame,est_x_mm,est_y_mm,est_theta_rad");
  out.Text(truth ? ",true_x_mm,true_y_mm,true_theta_rad\n" : "\n");
  for (const SubjectAnalysis& a : report.subjects) {
    for (size_t g = 0; g < a.est_errors.size(); ++g) {
      const stats::ErrorSegment& e = a.est_errors[g];
      std::string prefix;  // the subject and run cells and the comma after them
      io::CsvWriter(&prefix).Cells({a.subject, report.runs[static_cast<size_t>(e.run)], ""});
      const stats::ErrorSegment* t = truth ? &a.true_errors[g] : nullptr;
      for (size_t i = 0; i < e.frame.size(); ++i) out.Row(prefix, e.frame[i], e, i, t);
    }
  }
  out.Flush();
}

std::string AnalyzeErrorsCsv(const AnalyzeReport& report) {
  std::string csv;
  WriteAnalyzeErrorsCsv(report, [&csv](std::string_view piece) { csv.append(piece); });
  return csv;
}

std::string AnalyzeManifestJson(const AnalyzeReport& report, const std::vector<std::string>& inputs,
                                const std::vector<std::string>& outputs) {
  const AnalyzeOptions& o = report.options;
  nlohmann::json j;
  j["tool"] = "patlab analyze";
  j["version"] = PATLAB_VERSION;
  j["inputs"] = inputs;
  j["analysis"] = {{"smoothing_sigma_samples", o.smoothing.sigma_samples},
                   {"truncate_sigmas", o.smoothing.truncate_sigmas},
                   {"kernel_radius_samples", report.radius},
                   {"min_segment_samples", report.min_segment},
                   {"lag", o.lag},
                   {"correct_bias", o.correct_bias},
                   {"along_travel", o.along_travel},
                   {"white_noise_residual_factor", report.residual_factor},
                   {"white_noise_residual_lag_correlation", report.white_noise_lag}};
  j["runs"] = report.runs;
  nlohmann::json subjects = nlohmann::json::array();
  for (const SubjectAnalysis& a : report.subjects) {
    nlohmann::json s = {{"subject", a.subject},
                        {"samples", a.samples},
                        {"segments", a.segments},
                        {"skipped_segments", a.skipped_segments},
                        {"skipped_samples", a.skipped_samples},
                        {"est", SummaryJson(a.est)}};
    if (a.has_truth) s["true"] = SummaryJson(a.truth);
    subjects.push_back(s);
  }
  j["subjects"] = subjects;
  j["outputs"] = io::OutputNames(outputs);
  return j.dump(2) + "\n";
}

}  // namespace patlab::analysis

// The outputs of `patlab analyze` (analyze.h): Table I as CSV, the per-sample errors (streamed)
// and the JSON manifest.
#include <charconv>
#include <cstring>
#include <nlohmann/json.hpp>

#include "patlab/analysis/analyze.h"
#include "patlab/analysis/analyze_internal.h"
#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"

namespace patlab::analysis {

namespace {

std::string Fixed(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  return {buf, r.ptr};
}

nlohmann::json StdJson(const stats::StdWithCi& s, const stats::StdWithCi& iid,
                       const stats::EffectiveSize& size) {
  return {{"std", s.std},           {"lower", s.lower},
          {"upper", s.upper},       {"n", s.n},
          {"iid_lower", iid.lower}, {"iid_upper", iid.upper},
          {"lag1", size.lag1},      {"tau", size.tau},
          {"tau_lags", size.lags},  {"dof_effective", (static_cast<double>(s.n) - 1.0) / size.tau}};
}

nlohmann::json SummaryJson(const stats::ErrorSummary& s) {
  nlohmann::json j = {{"x", StdJson(s.x, s.x_iid, s.size_x)},
                      {"y", StdJson(s.y, s.y_iid, s.size_y)},
                      {"mean_x", s.mean_x},
                      {"mean_y", s.mean_y},
                      {"lag_x", s.lag_x},
                      {"lag_y", s.lag_y}};
  if (s.has_theta) j["theta"] = StdJson(s.theta, s.theta_iid, s.size_theta);
  return j;
}

}  // namespace

std::string AnalyzeTableCsv(const AnalyzeReport& report) {
  const std::string lag = std::to_string(report.options.lag);
  std::string csv =
      "subject,n,samples,segments,skipped_segments,skipped_samples,sx_mm,sx_lo,sx_hi,sx_iid_lo,"
      "sx_iid_hi,sy_mm,sy_lo,sy_hi,sy_iid_lo,sy_iid_hi,stheta_rad,stheta_lo,stheta_hi,"
      "stheta_iid_lo,stheta_iid_hi,lag" +
      lag + "_x,lag" + lag +
      "_y,true_sx_mm,true_sx_lo,true_sx_hi,true_sx_iid_lo,true_sx_iid_hi,true_sy_mm,true_sy_lo,"
      "true_sy_hi,true_sy_iid_lo,true_sy_iid_hi,true_stheta_rad,true_stheta_lo,true_stheta_hi,"
      "true_stheta_iid_lo,true_stheta_iid_hi,true_mean_x_mm,true_mean_y_mm\n";
  io::CsvWriter w(&csv);
  auto ci = [&w](const stats::StdWithCi& s, const stats::StdWithCi& iid, bool present,
                 int decimals) {
    if (!present) {
      w.Cells({"", "", "", "", ""});
      return;
    }
    w.Cells({Fixed(s.std, decimals), Fixed(s.lower, decimals), Fixed(s.upper, decimals),
             Fixed(iid.lower, decimals), Fixed(iid.upper, decimals)});
  };
  for (const SubjectAnalysis& a : report.subjects) {
    const stats::ErrorSummary& e = a.est;
    const stats::ErrorSummary& t = a.truth;
    const bool tt = a.has_truth && t.has_theta;
    w.Cell(a.subject);
    w.Cell(static_cast<int64_t>(e.x.n)).Cell(static_cast<int64_t>(a.samples));
    w.Cell(static_cast<int64_t>(a.segments)).Cell(static_cast<int64_t>(a.skipped_segments));
    w.Cell(static_cast<int64_t>(a.skipped_samples));
    ci(e.x, e.x_iid, true, 4);
    ci(e.y, e.y_iid, true, 4);
    ci(e.theta, e.theta_iid, e.has_theta, 6);
    w.Cells({Fixed(e.lag_x, 3), Fixed(e.lag_y, 3)});
    ci(t.x, t.x_iid, a.has_truth, 4);
    ci(t.y, t.y_iid, a.has_truth, 4);
    ci(t.theta, t.theta_iid, tt, 6);
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
  j["analysis"] = {{"detrend", NameOf(o.detrend, kDetrendNames)},
                   {"std_interval_method", stats::kStdIntervalMethod},
                   {"smoothing_sigma_samples", o.smoothing.sigma_samples},
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

#include "patlab/analysis/track_report.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/csv.h"
#include "patlab/stats/smoothing.h"

namespace patlab::analysis {

namespace {

// One subject's errors (estimated or true) as ErrorSegments, one per run, for error_stats.h.
std::vector<stats::ErrorSegment> Segments(const std::vector<SubjectRun>& runs, bool est) {
  std::vector<stats::ErrorSegment> segments(runs.size());
  for (size_t run = 0; run < runs.size(); ++run) {
    const SubjectRun& r = runs[run];
    stats::ErrorSegment& s = segments[run];
    s.run = static_cast<int>(run);
    s.frame.assign(r.sample.begin(), r.sample.end());
    s.x = est ? r.est_x_mm : r.true_x_mm;
    s.y = est ? r.est_y_mm : r.true_y_mm;
    s.theta = est ? r.est_theta_rad : r.true_theta_rad;
  }
  return segments;
}

TableRow MakeRow(const std::string& subject, const std::vector<SubjectRun>& runs,
                 int smoothing_radius) {
  TableRow row;
  row.subject = subject;
  size_t samples = 0;
  for (const SubjectRun& r : runs) {
    row.missed_frames += r.missed_frames;
    samples += r.sample.size();
  }
  if (samples < 2) {
    throw InputError("subject " + row.subject + " was found in fewer than 2 frames; expected a " +
                     "patch the segmentation can see (check the levels and the noise)");
  }
  const stats::ErrorSummary est =
      stats::SummariseErrors(Segments(runs, true), 1, 2 * smoothing_radius);
  const stats::ErrorSummary truth = stats::SummariseErrors(Segments(runs, false));
  row.est_x = est.x;
  row.est_y = est.y;
  row.true_x = truth.x;
  row.true_y = truth.y;
  row.est_x_iid = est.x_iid;
  row.est_y_iid = est.y_iid;
  row.true_x_iid = truth.x_iid;
  row.true_y_iid = truth.y_iid;
  row.est_size_x = est.size_x;
  row.est_size_y = est.size_y;
  row.true_size_x = truth.size_x;
  row.true_size_y = truth.size_y;
  row.true_mean_x_mm = truth.mean_x;
  row.true_mean_y_mm = truth.mean_y;
  row.est_lag1_x = est.lag_x;
  row.est_lag1_y = est.lag_y;
  row.has_theta = est.has_theta;
  row.est_theta = est.theta;
  row.true_theta = truth.theta;
  return row;
}

nlohmann::json TrackStdJson(const stats::StdWithCi& s) {
  return {{"std", s.std}, {"lower", s.lower}, {"upper", s.upper}, {"n", s.n}};
}

nlohmann::json TrackStdJson(const stats::StdWithCi& s, const stats::StdWithCi& iid,
                            const stats::EffectiveSize& size) {
  nlohmann::json j = TrackStdJson(s);
  j["iid_lower"] = iid.lower;
  j["iid_upper"] = iid.upper;
  j["lag1"] = size.lag1;
  j["tau"] = size.tau;
  j["tau_lags"] = size.lags;
  return j;
}

nlohmann::json TableJson(const std::vector<TableRow>& table) {
  nlohmann::json rows = nlohmann::json::array();
  for (const TableRow& r : table) {
    nlohmann::json row = {{"subject", r.subject},
                          {"est_x", TrackStdJson(r.est_x, r.est_x_iid, r.est_size_x)},
                          {"est_y", TrackStdJson(r.est_y, r.est_y_iid, r.est_size_y)},
                          {"true_x", TrackStdJson(r.true_x, r.true_x_iid, r.true_size_x)},
                          {"true_y", TrackStdJson(r.true_y, r.true_y_iid, r.true_size_y)},
                          {"missed_frames", r.missed_frames}};
    if (r.has_theta) {
      row["est_theta"] = TrackStdJson(r.est_theta);
      row["true_theta"] = TrackStdJson(r.true_theta);
    }
    rows.push_back(row);
  }
  return rows;
}

// The experiment's options as the manifest records them, table by table as in the file.
void AddOptionsJson(const TrackOptions& o, nlohmann::json* j) {
  (*j)["platform"] = {{"samples_per_run", o.samples_per_run},
                      {"rate_hz", o.rate_hz},
                      {"speed_mm_per_s", o.speed_mm_per_s},
                      {"heading_max_deg", o.heading_max_deg},
                      {"lateral_range_mm", o.lateral_range_mm},
                      {"start_jitter_mm", o.start_jitter_mm},
                      {"spacing_mm", o.spacing_mm},
                      {"plane_height_mm", o.plane_height_mm}};
  (*j)["camera"] = {{"height_mm", o.camera.height_mm},
                    {"image_size_px", {o.camera.image_width_px, o.camera.image_height_px}},
                    {"focal_length_px", o.camera.focal_length_px},
                    {"mm_per_px", MmPerPixel(o)}};
  (*j)["render"] = {{"background_level", o.background_level},
                    {"patch_level", o.patch_level},
                    {"threshold_level", o.threshold_level},
                    {"supersampling", o.supersampling}};
  (*j)["noise"] = {{"pixel_sigma", o.pixel_sigma}, {"jitter_sigma_px", o.jitter_sigma_px}};
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  (*j)["analysis"] = {{"smoothing_sigma_samples", o.smoothing_sigma_samples},
                      {"trim_samples", o.trim_samples},
                      {"white_noise_residual_factor", stats::ResidualStdFactor(smoothing)}};
}

}  // namespace

std::vector<TableRow> MakeTable(const TrackResult& result) {
  std::vector<TableRow> rows;
  for (size_t k = 0; k < result.subjects.size(); ++k) {
    rows.push_back(MakeRow(result.subjects[k], result.data[k], result.smoothing_radius));
  }
  return rows;
}

std::vector<SizeTest> MakeSizeTests(const TrackResult& result) {
  std::vector<SizeTest> tests;
  std::vector<std::string> discs;
  for (const std::string& s : result.subjects) {
    if (s.ends_with("mm")) discs.push_back(s);
  }
  for (const bool est : {true, false}) {
    std::vector<std::vector<stats::ErrorSegment>> errors;
    for (size_t k = 0; k < discs.size(); ++k) errors.push_back(Segments(result.data[k], est));
    std::vector<const std::vector<stats::ErrorSegment>*> pointers;
    for (const auto& e : errors) pointers.push_back(&e);
    const std::vector<SizeTest> some =
        stats::PairedAbsErrorTests(est ? "est" : "true", discs, pointers);
    tests.insert(tests.end(), some.begin(), some.end());
  }
  return tests;
}

std::string TableCsv(const std::vector<TableRow>& rows) {
  std::string csv =
      "subject,n,est_sx_mm,est_sx_lo,est_sx_hi,est_sx_iid_lo,est_sx_iid_hi,est_sy_mm,est_sy_lo,"
      "est_sy_hi,est_sy_iid_lo,est_sy_iid_hi,true_sx_mm,true_sx_lo,true_sx_hi,true_sx_iid_lo,"
      "true_sx_iid_hi,true_sy_mm,true_sy_lo,true_sy_hi,true_sy_iid_lo,true_sy_iid_hi,"
      "est_over_true_x,est_over_true_y,"
      "true_mean_x_mm,true_mean_y_mm,est_lag1_x,est_lag1_y,est_stheta_rad,true_stheta_rad,"
      "missed_frames\n";
  io::CsvWriter w(&csv);
  auto ci = [&w](const stats::StdWithCi& s, const stats::StdWithCi& iid) {
    w.Cells({FormatFixed(s.std, 4), FormatFixed(s.lower, 4), FormatFixed(s.upper, 4),
             FormatFixed(iid.lower, 4), FormatFixed(iid.upper, 4)});
  };
  auto theta = [](const TableRow& r, const stats::StdWithCi& s) {
    return r.has_theta ? FormatSignificant(s.std, 4) : std::string();
  };
  for (const TableRow& r : rows) {
    w.Cell(r.subject).Cell(static_cast<int64_t>(r.est_x.n));
    ci(r.est_x, r.est_x_iid);
    ci(r.est_y, r.est_y_iid);
    ci(r.true_x, r.true_x_iid);
    ci(r.true_y, r.true_y_iid);
    w.Cells({FormatFixed(r.est_x.std / r.true_x.std, 3), FormatFixed(r.est_y.std / r.true_y.std, 3),
             FormatFixed(r.true_mean_x_mm, 4), FormatFixed(r.true_mean_y_mm, 4),
             FormatFixed(r.est_lag1_x, 3), FormatFixed(r.est_lag1_y, 3), theta(r, r.est_theta),
             theta(r, r.true_theta)})
        .Cell(static_cast<int64_t>(r.missed_frames))
        .EndRow();
  }
  return csv;
}

std::string SizeTestsCsv(const std::vector<SizeTest>& tests) {
  return stats::PairedTestsCsv(tests);
}

std::string ErrorsCsv(const TrackOptions& options, const TrackResult& result, int decimate) {
  PATLAB_CHECK(decimate >= 1);
  std::string csv =
      "subject,run,frame,t_s,est_x_mm,est_y_mm,true_x_mm,true_y_mm,est_theta_rad,"
      "true_theta_rad\n";
  for (size_t k = 0; k < result.subjects.size(); ++k) {
    for (size_t run = 0; run < result.data[k].size(); ++run) {
      const SubjectRun& r = result.data[k][run];
      for (size_t i = 0; i < r.sample.size(); ++i) {
        // Every decimate-th sample and its successor: adjacent pairs survive for Fig. 6.
        if (i % static_cast<size_t>(decimate) > 1) continue;
        io::AppendCsvCell(result.subjects[k], &csv);
        csv += StringPrintf(",%zu,%d,%.4f,%.4f,%.4f,%.4f,%.4f,", run, r.sample[i],
                            r.sample[i] / options.rate_hz, r.est_x_mm[i], r.est_y_mm[i],
                            r.true_x_mm[i], r.true_y_mm[i]);
        csv += r.est_theta_rad.empty()
                   ? std::string(",")
                   : StringPrintf("%.6f,%.6f", r.est_theta_rad[i], r.true_theta_rad[i]);
        csv += "\n";
      }
    }
  }
  return csv;
}

std::string TrackManifestJson(const TrackOptions& o, const TrackResult& result,
                              const std::vector<TableRow>& table,
                              const std::vector<std::string>& outputs) {
  nlohmann::json j;
  j["tool"] = "patlab track";
  j["version"] = PATLAB_VERSION;
  j["experiment"] = o.source_file;
  j["name"] = o.name;
  j["description"] = o.description;
  j["seed"] = o.seed;
  j["runs"] = o.runs;
  j["diameters_mm"] = o.diameters_mm;
  j["pattern_file"] = o.pattern_file;
  AddOptionsJson(o, &j);
  nlohmann::json runs = nlohmann::json::array();
  for (const RunSetup& s : result.setups) {
    runs.push_back({{"heading_deg", s.heading_rad * 180.0 / std::numbers::pi},
                    {"start_mm", {s.start_mm.x(), s.start_mm.y()}}});
  }
  j["run_setups"] = runs;
  j["table"] = TableJson(table);
  j["outputs"] = io::OutputNames(outputs);
  return j.dump(2) + "\n";
}

}  // namespace patlab::analysis

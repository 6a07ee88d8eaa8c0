// RunNoiseFitStudy (noise_fit.h): the fit, candidate models, the geometry sensitivity and the
// blob-level check, as CSV text.
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "patlab/core/format.h"
#include "patlab/core/options.h"
#include "patlab/io/csv.h"
#include "patlab/paper/noise_fit.h"

namespace patlab::paper {

namespace {

std::string Num(double v) { return FormatSignificant(v, 6); }

std::string MechName(int j) {
  return std::string(kMechanismNames.entries[static_cast<size_t>(j)].second);
}

struct Candidate {
  const char* name;
  std::vector<Mechanism> free;
};

const std::vector<Candidate>& Candidates() {
  using M = Mechanism;
  static const std::vector<Candidate> c = {
      {"independent", {M::kIndependentX, M::kIndependentY}},
      {"independent+common", {M::kIndependentX, M::kIndependentY, M::kCommon}},
      {"independent+common+roll", {M::kIndependentX, M::kIndependentY, M::kCommon, M::kRoll}},
      {"independent+common+scale", {M::kIndependentX, M::kIndependentY, M::kCommon, M::kScale}},
      {"independent+common+correlated",
       {M::kIndependentX, M::kIndependentY, M::kCommon, M::kCorrelated}},
      {"independent+common+colour", {M::kIndependentX, M::kIndependentY, M::kCommon, M::kColour}},
      {"independent+colour", {M::kIndependentX, M::kIndependentY, M::kColour}},
      {"independent+roll", {M::kIndependentX, M::kIndependentY, M::kRoll}},
      {"all",
       {M::kIndependentX, M::kIndependentY, M::kCommon, M::kRoll, M::kScale, M::kCorrelated,
        M::kColour}},
  };
  return c;
}

NoiseFitOptions WithFree(const NoiseFitOptions& base, const std::vector<Mechanism>& free,
                         int profile_points, int bootstrap) {
  NoiseFitOptions o = base;
  o.free = {};
  o.fixed = {};
  for (Mechanism m : free) o.free[static_cast<size_t>(m)] = true;
  o.profile_points = profile_points;
  o.bootstrap = bootstrap;
  return o;
}

// The Butterfly rows' largest |observed - predicted| / se.
double WorstButterflyZ(const FitDesign& design, const NoiseFitResult& r) {
  double worst = 0.0;
  for (size_t i = 0; i < design.data.size(); ++i) {
    if (design.data[i].table1) continue;
    worst = std::max(worst, std::abs(design.data[i].observed - r.predicted[i]) / design.data[i].se);
  }
  return worst;
}

// The study's steps (NoiseFitStudyOptions::progress): counted as they are done.
class Steps {
 public:
  Steps(std::function<void(int, int)> progress, int total)
      : progress_(std::move(progress)), total_(total) {}
  void operator()() {
    if (progress_) progress_(++done_, total_);
  }
  std::function<void()> Callback() {
    if (!progress_) return {};
    return [this] { (*this)(); };
  }

 private:
  std::function<void(int, int)> progress_;
  int total_ = 0, done_ = 0;
};

constexpr int kSensitivityModels = 2;  // the models SensitivityCsv fits per radius

// The study's steps in all: the main fit's (FitNoise), the models', the sensitivity fits and
// the blob-level check.
int StudySteps(const NoiseFitStudyOptions& o) {
  int free = 0;
  for (bool f : o.fit.free) free += f ? 1 : 0;
  return 1 + free + (o.fit.bootstrap >= 2 ? o.fit.bootstrap : 0) +
         static_cast<int>(Candidates().size()) +
         kSensitivityModels * static_cast<int>(o.sensitivity_radii_mm.size()) +
         (o.simulate_runs > 0 ? 1 : 0);
}

std::string ModelsCsv(const FitDesign& design, const NoiseFitOptions& base, Steps* steps) {
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cells({"model", "parameters", "minus2_log_l", "aic", "chi2", "delta_mm"});
  for (int j = 0; j < kNumMechanisms; ++j) w.Cell(MechName(j));
  w.Cells({"pred_butterfly_x", "pred_butterfly_y", "pred_butterfly_theta", "worst_butterfly_z"});
  w.EndRow();
  for (const Candidate& c : Candidates()) {
    const NoiseFitResult r = FitNoise(design, WithFree(base, c.free, 3, 0));
    w.Cell(c.name).Cell(static_cast<int64_t>(r.free_parameters));
    for (double v : {r.minus2_log_l, r.minus2_log_l + 2.0 * r.free_parameters, r.chi2, r.delta})
      w.Cell(Num(v));
    for (int j = 0; j < kNumMechanisms; ++j) w.Cell(Num(r.best[j]));
    for (size_t i = design.data.size() - 3; i < design.data.size(); ++i)
      w.Cell(Num(r.predicted[i]));
    w.Cell(Num(WorstButterflyZ(design, r))).EndRow();
    (*steps)();
  }
  return csv;
}

// Per assumed Butterfly size: the colour model's magnitudes with profile intervals, and how well
// the independent+common model (no colour excess) does.
std::string SensitivityCsv(const NoiseFitStudyOptions& o, const std::vector<FitDatum>& data,
                           Steps* steps) {
  using M = Mechanism;
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cells({"id_radius_mm", "model", "minus2_log_l", "chi2", "worst_butterfly_z", "mechanism",
           "value", "lower", "upper", "verdict"})
      .EndRow();
  for (double radius : o.sensitivity_radii_mm) {
    NoiseFitGeometry g = o.geometry;
    g.id_radius_mm = radius;
    double delta = 0.0;
    const FitDesign design = AddTable1Discrepancy(BuildDesign(data, g), &delta);
    for (const Candidate& c :
         {Candidate{"independent+common+colour",
                    {M::kIndependentX, M::kIndependentY, M::kCommon, M::kColour}},
          Candidate{"independent+common", {M::kIndependentX, M::kIndependentY, M::kCommon}}}) {
      const NoiseFitResult r = FitNoise(design, WithFree(o.fit, c.free, 21, 0));
      for (const MechanismEstimate& e : r.estimates) {
        if (!e.free) continue;
        w.Cell(Num(radius)).Cell(c.name);
        for (double v : {r.minus2_log_l, r.chi2, WorstButterflyZ(design, r)}) w.Cell(Num(v));
        w.Cell(MechName(static_cast<int>(e.mechanism)));
        for (double v : {e.value, e.lower, e.upper}) w.Cell(Num(v));
        w.Cell(NameOf(e.verdict, kIdentifiabilityNames)).EndRow();
      }
      (*steps)();
    }
  }
  return csv;
}

std::string FitCsv(const NoiseFitResult& r, double delta) {
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cells({"mechanism", "free", "value", "lower", "upper", "boot_lower", "boot_upper", "verdict",
           "most_correlated", "correlation"})
      .EndRow();
  for (const MechanismEstimate& e : r.estimates) {
    w.Cell(MechName(static_cast<int>(e.mechanism))).Cell(e.free ? "1" : "0");
    for (double v : {e.value, e.lower, e.upper, e.boot_lower, e.boot_upper}) w.Cell(Num(v));
    w.Cell(NameOf(e.verdict, kIdentifiabilityNames));
    w.Cell(e.most_correlated >= 0 ? MechName(e.most_correlated) : "");
    w.Cell(Num(e.correlation)).EndRow();
  }
  w.Cells({"delta_mm", "0", Num(delta), "", "", "", "", "", "", ""}).EndRow();
  return csv;
}

std::string ProfilesCsv(const NoiseFitResult& r) {
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cells({"mechanism", "value", "minus2_delta_log_l"}).EndRow();
  for (const MechanismEstimate& e : r.estimates)
    for (const ProfilePoint& p : e.profile)
      w.Cells({MechName(static_cast<int>(e.mechanism)), Num(p.value), Num(p.minus2_log_l)})
          .EndRow();
  return csv;
}

std::string CorrelationCsv(const NoiseFitResult& r) {
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cell("mechanism");
  for (int j = 0; j < kNumMechanisms; ++j) w.Cell(MechName(j));
  w.EndRow();
  for (int a = 0; a < kNumMechanisms; ++a) {
    w.Cell(MechName(a));
    for (int b = 0; b < kNumMechanisms; ++b)
      w.Cell(Num(r.correlation[static_cast<size_t>(a * kNumMechanisms + b)]));
    w.EndRow();
  }
  return csv;
}

std::string DataCsv(const FitDesign& design, const NoiseFitResult& r,
                    const std::vector<double>& simulated) {
  std::string csv;
  io::CsvWriter w(&csv);
  w.Cells({"datum", "observed", "se", "quantisation", "predicted", "z", "simulated"}).EndRow();
  for (size_t i = 0; i < design.data.size(); ++i) {
    const FitDatum& d = design.data[i];
    const double s = std::sqrt(d.se * d.se + (d.table1 ? r.delta * r.delta : 0.0));
    w.Cell(d.name);
    for (double v :
         {d.observed, d.se, d.quantisation, r.predicted[i], (d.observed - r.predicted[i]) / s,
          simulated.empty() ? std::nan("") : simulated[i]})
      w.Cell(Num(v));
    w.EndRow();
  }
  return csv;
}

}  // namespace

namespace {
// The blob-level check simulates simulate_runs x simulate_frames frames: bounded so that a typo
// (--simulate-runs 2000000000) is refused before work instead of running until killed.
constexpr int64_t kMaxSimulateRuns = 1000;
constexpr int64_t kMaxSimulateFrames = 1000000;
}  // namespace

NoiseFitStudy RunNoiseFitStudy(const NoiseFitStudyOptions& o) {
  Validate(o.fit);
  OptionsChecker check;
  check.IntegerInRange("simulate_runs", o.simulate_runs, 0, kMaxSimulateRuns)
      .IntegerInRange("simulate_frames", o.simulate_frames, 1, kMaxSimulateFrames);
  ThrowFirstProblem(check.Take());
  const std::vector<FitDatum> data = PaperData(o.paper);
  double delta = 0.0;
  const FitDesign design = AddTable1Discrepancy(BuildDesign(data, o.geometry), &delta);
  NoiseFitStudy study;
  Steps steps(o.progress, StudySteps(o));
  study.fit = FitNoise(design, o.fit, steps.Callback());
  std::vector<double> simulated;
  if (o.simulate_runs > 0) {
    simulated = SimulateTrack(data, o.geometry, study.fit.best, o.simulate_runs, o.simulate_frames,
                              o.fit.seed);
    steps();
  }
  study.files = {{"fit.csv", FitCsv(study.fit, delta)},
                 {"data.csv", DataCsv(design, study.fit, simulated)},
                 {"profiles.csv", ProfilesCsv(study.fit)},
                 {"correlation.csv", CorrelationCsv(study.fit)},
                 {"models.csv", ModelsCsv(design, o.fit, &steps)},
                 {"sensitivity.csv", SensitivityCsv(o, data, &steps)}};
  study.summary = "-2 log L " + FormatFixed(study.fit.minus2_log_l, 2) + ", chi2 " +
                  FormatFixed(study.fit.chi2, 2) + " (9 data), Table I discrepancy delta " +
                  FormatFixed(delta, 4) + " mm\n";
  for (const MechanismEstimate& e : study.fit.estimates) {
    if (!e.free) continue;
    study.summary += MechName(static_cast<int>(e.mechanism)) + " " + FormatSignificant(e.value, 3) +
                     " [" + FormatSignificant(e.lower, 3) + ", " + FormatSignificant(e.upper, 3) +
                     "] " + std::string(NameOf(e.verdict, kIdentifiabilityNames)) + "\n";
  }
  return study;
}

}  // namespace patlab::paper

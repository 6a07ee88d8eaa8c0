#include "patlab/sim/experiment.h"

#include <cmath>

#include "patlab/core/format.h"

namespace patlab::sim {

void CheckTrials(int64_t trials, std::string_view field, OptionsChecker* check) {
  check->IntegerInRange(field, trials, kMinTrials, kMaxTrials);
}

void CheckFrames(int64_t frames, std::string_view field, OptionsChecker* check) {
  check->IntegerInRange(field, frames, 1, kMaxFrames);
}

void CheckFieldSides(double length_mm, double width_mm, std::string_view length_field,
                     std::string_view width_field, OptionsChecker* check) {
  check->InRange(length_field, length_mm, 0.0, kMaxFieldSideMm, "mm")
      .InRange(width_field, width_mm, 0.0, kMaxFieldSideMm, "mm");
}

void CheckSigmas(std::span<const double> sigmas_mm, std::string_view field, OptionsChecker* check) {
  const std::string expected = "strictly increasing finite numbers >= 0 (mm)";
  if (sigmas_mm.empty()) {
    check->Fail(field, check->Name(field) + " is empty; expected " + expected);
    return;
  }
  for (size_t k = 0; k < sigmas_mm.size(); ++k) {
    const double s = sigmas_mm[k];
    if (!std::isfinite(s) || s < 0.0 || (k > 0 && !(s > sigmas_mm[k - 1]))) {
      check->Fail(field, check->Name(field) + " has " + FormatNumber(s) + "; expected " + expected);
      return;
    }
  }
}

std::vector<OptionsProblem> Check(const DetectSettings& settings) {
  OptionsChecker check;
  CheckFrames(settings.frames, "frames", &check);
  check.Positive("match_radius_mm", settings.match_radius_mm, "mm");
  std::vector<OptionsProblem> problems = check.Take();
  for (OptionsProblem& problem : Check(settings.scene)) problems.push_back(std::move(problem));
  return problems;
}

std::vector<OptionsProblem> Check(const Experiment& e) {
  OptionsChecker check;
  const bool detect_mode = e.correspondence == Correspondence::kDetect;
  if (!detect_mode) CheckTrials(e.trials, "trials", &check);
  CheckSigmas(e.sigmas_mm, "sigmas_mm", &check);
  CheckFieldSides(e.field_length_mm, e.field_width_mm, "field_length_mm", "field_width_mm", &check);
  std::vector<OptionsProblem> problems = check.Take();
  const auto append = [&problems](std::vector<OptionsProblem> more) {
    for (OptionsProblem& problem : more) problems.push_back(std::move(problem));
  };
  append(Check(e.noise));
  if (detect_mode) {
    append(Check(e.detect));
  } else {
    append(estimate::Check(e.ml_options));
  }
  return problems;
}

void Validate(const Experiment& experiment) { ThrowFirstProblem(Check(experiment)); }

void ApplyOverrides(const Overrides& overrides, Experiment* experiment) {
  OptionsChecker check;
  if (overrides.trials && experiment->correspondence == Correspondence::kDetect) {
    CheckFrames(*overrides.trials, "--trials", &check);
    if (!check.problems().empty()) {
      throw InputError(check.problems().front().message + " (frames per point in detect mode)");
    }
    experiment->detect.frames = *overrides.trials;
  } else if (overrides.trials) {
    CheckTrials(*overrides.trials, "--trials", &check);
    ThrowFirstProblem(check.problems());
    experiment->trials = *overrides.trials;
  }
  if (overrides.seed) experiment->seed = *overrides.seed;
  if (!overrides.sigmas_mm.empty()) {
    CheckSigmas(overrides.sigmas_mm, "--sigmas", &check);
    ThrowFirstProblem(check.problems());
    experiment->sigmas_mm = overrides.sigmas_mm;
  }
}

}  // namespace patlab::sim

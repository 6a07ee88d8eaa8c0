// The cameras of the lines weighed by the robots decoded through each (camera_setup.h,
// SetupRival): the lines' rivals, where the lines do not decide, and their runners-up, where no
// robot decodes through the camera the lines chose.
#include <algorithm>
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/camera_setup_internal.h"

namespace patlab::formats {
namespace {

// One camera of the lines with its files, height and the robots it is credited with.
struct Weighed {
  SetupResult setup;
  SetupRival rival;
};

// Cameras are compared by the robots each is credited with at its chosen height: through the
// lines' height of a camera whose height they do not measure, the robots decoded tell its scale's
// luck, not its place (few-lines view 8: 5 robots through one corner's camera, 3 and 0 through the
// others', 10 through each at some height; the 5 kept: 10 false IDs).
Weighed Weigh(const std::vector<const camera::Image*>& frames,
              const std::vector<std::string>& names, const detect::DetectorConfig& config,
              const SetupOptions& options, const calib::AutoCalibration& a, int model,
              double floor_difference_mm, const std::vector<Weighed>& before) {
  Weighed w;
  internal::UseCalibration(a, options.fields[static_cast<size_t>(model)], &w.setup);
  if (!before.empty()) w.setup.normalised_frames = before.front().setup.normalised_frames;
  internal::FinishSetup(frames, names, config, options, w.setup);
  internal::ChooseHeight(frames, names, config, options, w.setup);
  w.rival = {w.setup.field.name, a.score_px, floor_difference_mm,
             internal::CreditedRobots(w.setup.height)};
  return w;
}

// Whether no robot decodes through the camera at its height or any other the height scan tried.
bool DecodesNone(const SetupResult& r) {
  return std::max(r.robots_by_blobs, r.robots_by_pixels) == 0 &&
         internal::MostRobotsTried(r.height) == 0 && r.height.robots == 0;
}

// Neither the lines nor the robots decide between cameras that map the frame differently: the
// line length kept was a coin toss (fresh rendered seed 87: two models' cameras 2.6 m apart,
// 1976.4 and 1974.3 px of line, 8 robots each; the one kept put every robot 2.6 m off), so setup
// refuses with the numbers rather than write either.
void RefuseUndecided(const std::string& frame, const std::vector<SetupRival>& undecided) {
  std::string cameras;
  bool models_differ = false;
  for (size_t i = 0; i < undecided.size(); ++i) {
    const SetupRival& u = undecided[i];
    if (i > 0 && u.robots < undecided.front().robots) continue;
    models_differ = models_differ || u.field != undecided.front().field;
    cameras += (cameras.empty() ? "" : "; ") + u.field + " explaining " +
               FormatSignificant(u.score_px, 5) + " px of line, " + std::to_string(u.robots) +
               " robots decoded where its height is measured, mapping the frame " +
               FormatSignificant(u.floor_difference_mm, 3) + " mm from the lines' best camera";
  }
  // Naming the model decides only between cameras of different models: two cameras of the
  // model named stay tied (rendered seed 87 with ssl-2018 named: a quarter turn of a centre view).
  throw InputError(frame + ": neither the lines nor the robots decide the camera (" + cameras +
                   "); expected a frame showing more of the field's lines, " +
                   (models_differ ? "or name the model with --field MODEL, " : "") +
                   "or give four --landmark NAME=X,Y (patlab setup --list-landmarks FIELD)");
}

}  // namespace

void internal::UseCalibration(const calib::AutoCalibration& a, const calib::Field& field,
                              SetupResult* r) {
  r->field = field;
  r->calibration_input = a.input;
  r->calibration_fit = a.fit;
  r->mapping_error_mm = a.held_out_mapping_mm;
  r->mapping_resolution_mm = a.held_out_resolution_mm;
  r->calibration_report = calib::AutoReportText(a);
}

SetupResult internal::WeighCameras(const std::vector<const camera::Image*>& frames,
                                   const std::vector<std::string>& names,
                                   const detect::DetectorConfig& config,
                                   const SetupOptions& options, calib::FamilyCalibration& family,
                                   std::string* at_bound) {
  std::vector<Weighed> weighed;
  weighed.push_back(
      Weigh(frames, names, config, options, family.calibration, family.kept, 0.0, weighed));
  for (const calib::FamilyRival& rival : family.rivals) {
    weighed.push_back(Weigh(frames, names, config, options, rival.calibration, rival.model,
                            rival.floor_difference_mm, weighed));
  }
  const size_t rivals = weighed.size() - 1;
  // (FocalAtItsBound speaks only of a camera without rivals.)
  *at_bound = FocalAtItsBound(family, options.fields, names.front(), frames.front()->width_px,
                              weighed.front().setup.height);
  if (at_bound->empty()) {
    *at_bound =
        RobotsOnlyAtTheHighest(family, options.fields, names.front(), weighed.front().setup.height);
  }
  if (!at_bound->empty()) return {};
  // No robot decodes through any camera the lines left: where a camera the lines decided against
  // narrowly (a runner-up) is credited with robots, they weigh it (fresh rendered seed 334:
  // ssl-2012's camera, 0.61 m up, explained 1479 px of line, ssl-2018's true one 1287 px; no robot
  // decoded through the first, 8 through the second).
  bool overruled = false;
  if (std::all_of(weighed.begin(), weighed.end(),
                  [](const Weighed& w) { return DecodesNone(w.setup); })) {
    for (calib::FamilyRival& runner_up : family.runners_up) {
      calib::MeasureHeldOut(runner_up.calibration);
      weighed.push_back(Weigh(frames, names, config, options, runner_up.calibration,
                              runner_up.model, runner_up.floor_difference_mm, weighed));
      overruled = overruled || weighed.back().rival.robots > 0;
    }
    if (!overruled) weighed.resize(1 + rivals);
  }
  if (weighed.size() == 1) return std::move(weighed.front().setup);
  size_t chosen = 0;
  for (size_t i = 1; i < weighed.size(); ++i)
    if (weighed[i].rival.robots > weighed[chosen].rival.robots) chosen = i;
  SetupResult r = std::move(weighed[chosen].setup);
  r.undecided.push_back(weighed[chosen].rival);
  for (size_t i = 0; i < weighed.size(); ++i)
    if (i != chosen) r.undecided.push_back(weighed[i].rival);
  r.robots_decided = std::all_of(r.undecided.begin() + 1, r.undecided.end(), [&](const auto& u) {
    return u.robots < r.undecided.front().robots;
  });
  r.lines_overruled = overruled;
  if (!r.robots_decided) RefuseUndecided(names.front(), r.undecided);
  return r;
}

std::string internal::UndecidedText(const SetupResult& r) {
  // (Where the robots do not decide either, setup refuses: RefuseUndecided.)
  std::string s =
      r.lines_overruled
          ? " (no robot decodes through the lines' camera; the robots chose among it and the "
            "cameras the lines decided against narrowly)\n  cameras weighed by their robots"
          : " (the lines do not decide the camera; the robots do)\n  cameras the lines do not "
            "decide between";
  s += " (px of line explained, robots decoded through each where its height is measured, how "
       "far apart they map the frame from the lines' best):\n";
  for (size_t i = 0; i < r.undecided.size(); ++i) {
    const SetupRival& u = r.undecided[i];
    s += "  " + u.field + ": " + FormatSignificant(u.score_px, 5) + " px, " +
         std::to_string(u.robots) + " robots, " + FormatSignificant(u.floor_difference_mm, 3) +
         " mm" + (i == 0 ? " (kept)" : "") +
         (r.lines_overruled && u.floor_difference_mm == 0.0 ? " (the lines' best)" : "") + "\n";
  }
  return s;
}

}  // namespace patlab::formats

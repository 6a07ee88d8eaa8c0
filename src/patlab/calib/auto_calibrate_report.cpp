// The automatic field calibration's report (auto_calibrate.h): what was found, the symmetry and
// the held-out mapping error, then the fit's own report.
#include <string>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/core/format.h"

namespace patlab::calib {

std::string HeldOutText(const AutoCalibration& a) {
  if (a.held_out_mapping_mm < a.held_out_resolution_mm) {
    return "below " + FormatSignificant(a.held_out_resolution_mm, 2) +
           " mm (the line finder's resolution; estimate " +
           FormatSignificant(a.held_out_mapping_mm, 2) + " mm)";
  }
  return FormatSignificant(a.held_out_mapping_mm, 3) + " mm";
}

std::string AutoReportText(const AutoCalibration& a) {
  std::string s = "# automatic field calibration\n";
  s += "line pixels found: " + std::to_string(a.line_pixels) +
       "; assigned to the field's marks: " + std::to_string(a.assigned_pixels) + "\n";
  s += "observations: " + std::to_string(a.input.lines.size()) + " lines (";
  for (size_t i = 0; i < a.input.lines.size(); ++i) s += (i ? ", " : "") + a.input.lines[i].name;
  s += "), " + std::to_string(a.input.circles.size()) + " circles (";
  for (size_t i = 0; i < a.input.circles.size(); ++i)
    s += (i ? ", " : "") + a.input.circles[i].name;
  s += ")\n";
  s += "hypotheses scored: " + std::to_string(a.hypotheses) + "; best explains " +
       FormatSignificant(a.score_px, 5) + " px of line, the other refined one " +
       FormatSignificant(a.runner_up_px, 5) + " px\n";
  if (a.point_symmetric) {
    s += std::string(
             "symmetry: the field is the same rotated by 180 deg (mirrored about both "
             "axes); of the two equivalent cameras the one whose image centre looks at "
             "x >= 0 is kept") +
         (a.turned ? " (the search's camera was turned to it)" : "") + "\n";
  } else {
    s += "symmetry: none (the field is not the same rotated by 180 deg)\n";
  }
  s += "held-out mapping error: " + HeldOutText(a) +
       " RMS on the floor (estimated from the run means of the held-out pixels, the line "
       "finder's noise of " +
       FormatSignificant(a.held_out_noise_mm, 3) + " mm removed; resolution " +
       FormatSignificant(a.held_out_resolution_mm, 3) + " mm, twice the noise of a run's mean)\n";
  s += "held-out pixels: RMS " + FormatSignificant(a.held_out_rms_mm, 3) + " mm, worst " +
       FormatSignificant(a.held_out_worst_mm, 3) + " mm over " + std::to_string(a.held_out_count) +
       " line pixels (two folds of alternating runs of 8 along each mark; each pixel's floor "
       "distance to its mark through the camera fitted to the other fold)\n";
  for (const std::string& n : a.notes) s += "note: " + n + "\n";
  s += "seconds: " + FormatSignificant(a.seconds, 3) + "\n\n";
  return s + FitReportText(a.input, a.fit);
}

}  // namespace patlab::calib

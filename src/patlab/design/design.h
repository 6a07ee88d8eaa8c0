// Searching patch layouts for a better pattern (behind `patlab design`): the key patch sits at the
// origin (the robot's centre, the pose point) and the search moves the ID patches inside the robot
// top, keeping every patch apart by a minimum gap, to minimise one criterion subject to limits on
// the others. docs/design.md states the objective, the constraints and why NLopt's COBYLA.
//
// The criteria of a layout (all from the geometry alone, the same numbers `patlab compare` prints):
//  - angle CRLB: sigma_theta >= sigma / sqrt(sum |p_i - pbar|^2), mrad per mm of patch sigma
//    (estimate/bounds.h);
//  - position CRLB: the origin's per-axis std bound, mm per mm of patch sigma (estimate/bounds.h);
//  - ID capacity: the IDs with `palette` colours under the symmetry rule of detect/codebook.h;
//  - rotation onset: the patch sigma (mm) at which noise lets a wrong rotation that geometry must
//    reject pass the detector's test in 1 of 1000 fits (design/compare.h DesignGeometry); +inf when
//    colours decide every rotation.
// The search minimises `objective` subject to ids >= min_ids, onset >= min_rotation_onset_mm,
// angle CRLB <= max_angle_crlb_mrad_per_mm and position CRLB <= max_position_crlb_per_mm, and to
// the geometric constraints (every patch inside the diameter less rim_gap_mm, every pair of
// patches at least min_gap_mm apart edge to edge).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"

namespace patlab::design {

// What the search minimises (the other criteria enter as constraints).
enum class DesignObjective {
  kAngleCrlb,      // the angle CRLB (mrad per mm of patch sigma)
  kPositionCrlb,   // the position CRLB (mm per mm of patch sigma, per axis)
  kRotationOnset,  // minus the rotation onset (mm): the most robust rotation fix
};
inline constexpr EnumNames<DesignObjective, 3> kDesignObjectiveNames{{{
    {DesignObjective::kAngleCrlb, "angle_crlb"},
    {DesignObjective::kPositionCrlb, "position_crlb"},
    {DesignObjective::kRotationOnset, "rotation_onset"},
}}};

// The family of layouts searched. Symmetric layouts are a set of measure zero: a free search
// reaches one only by chance, so a family parametrises it directly.
enum class DesignSymmetry {
  kNone,    // every ID patch free (2 variables each)
  kMirror,  // mirror-symmetric about the x axis (front-back): pairs (x, y), (x, -y), and with
            // an odd number of ID patches one on the axis (x, 0)
  kCyclic,  // id_patches-fold rotational symmetry: one patch free, the others it turned by
            // multiples of 360 / id_patches degrees (the colours must then decide every rotation)
};
inline constexpr EnumNames<DesignSymmetry, 3> kDesignSymmetryNames{{{
    {DesignSymmetry::kNone, "none"},
    {DesignSymmetry::kMirror, "mirror"},
    {DesignSymmetry::kCyclic, "cyclic"},
}}};

struct DesignOptions {
  std::string name = "designed";  // the pattern's name in the file written
  // The robot top: every patch lies inside the circle of this diameter (mm) about the key patch
  // centre, at least rim_gap_mm (mm) from its edge. SSL robots: at most 180 mm.
  double outer_diameter_mm = 180.0;
  double rim_gap_mm = 0.0;
  double key_radius_mm = 25.0;  // the key (team colour) patch at the origin
  // The ID patches: how many, and their radii (mm): one value for all, or one per ID patch.
  int id_patches = 4;
  std::vector<double> id_radii_mm = {20.0};
  // The smallest edge-to-edge distance (mm) between two patches (key included). Larger gaps keep
  // blobs apart under blur and segmentation noise; smaller ones leave room to spread the dots.
  double min_gap_mm = 20.0;
  // ID colours (>= 2; the key colour is not counted): the ID capacity is counted for this many.
  int palette = 2;
  // The symmetry tolerance of the ID count (mm; detect::FindSymmetry, patlab ids --tolerance).
  double tolerance_mm = 10.0;

  DesignObjective objective = DesignObjective::kAngleCrlb;
  DesignSymmetry symmetry = DesignSymmetry::kNone;
  // Limits on the other criteria. min_ids = 0 asks for every colouring, palette^id_patches (the
  // geometry must then reject every wrong rotation); the others are off at their defaults.
  int64_t min_ids = 0;
  double min_rotation_onset_mm = 0.0;
  double max_angle_crlb_mrad_per_mm = std::numeric_limits<double>::infinity();
  double max_position_crlb_per_mm = std::numeric_limits<double>::infinity();

  // The search: `starts` local COBYLA runs from seeded random layouts (the first from start_mm
  // when given), each stopped after max_evaluations layouts or when no coordinate moves by more
  // than xtol_mm. More starts find the global optimum more surely and cost linearly more.
  int starts = 32;
  int max_evaluations = 4000;
  // Called after each start (starts done, starts); empty = no reports.
  std::function<void(int, int)> progress;
  double xtol_mm = 1e-5;
  uint64_t seed = 1;
  // Optional first start: one position (mm) per ID patch (e.g. a known design's), or empty.
  std::vector<Vec2> start_mm;
};
// Every limit of a single field, and the ones that make the layout impossible before any search:
// an ID patch wider than the ring between key and rim, or more patch area than the robot top has;
// symmetry cyclic with more IDs asked for (min_ids; 0 = all) than the regular layout can hold.
std::vector<OptionsProblem> Check(const DesignOptions& options);
void Validate(const DesignOptions& options);

// The constraints file of `patlab design --constraints FILE` (docs/file-formats.md): a TOML table
// whose keys are the fields above (id_radii_mm a number or an array; objective and symmetry by
// name; no start_mm). Absent keys keep `defaults`. The file's options must pass Check on their
// own. Throws InputError "file:line: ...; expected ..." at the offending key (an unknown key, a
// wrong type, a value out of range, constraints that cannot fit).
DesignOptions ParseDesignConstraints(std::string_view text, const std::string& file,
                                     DesignOptions defaults);
DesignOptions LoadDesignConstraints(const std::string& path, DesignOptions defaults);

// The criteria and geometric constraints of one layout.
struct DesignMetrics {
  double angle_crlb_mrad_per_mm = 0.0;
  double position_crlb_per_mm = 0.0;
  uint64_t ids = 0;                 // with options.palette colours
  double rotation_onset_mm = 0.0;   // +inf when colours decide every rotation
  double rotation_sigma0_mm = 0.0;  // the same without noise (design/compare.h); +inf likewise
  int rotations = 0;                // the effective symmetry group's order
  double min_gap_mm = 0.0;          // smallest edge-to-edge gap between two patches
  double rim_gap_mm = 0.0;          // outer_diameter_mm / 2 - max(|p_i| + r_i)
  bool feasible = false;            // every constraint of the options holds (no tolerance)
  std::string violated;             // the first constraint that does not hold, or empty
};

// The ID patch positions of the family's search variables (SymmetryVariables of them), and the
// variables of a layout (projected onto the family: the first patches' coordinates).
int SymmetryVariables(const DesignOptions& options);
std::vector<Vec2> ExpandSymmetry(const DesignOptions& options, const double* x);
std::vector<double> ReduceSymmetry(const DesignOptions& options, const std::vector<Vec2>& layout);

// The pattern with the key at the origin and the ID patches at `id_positions_mm` (IdSlots order).
Pattern DesignPattern(const DesignOptions& options, const std::vector<Vec2>& id_positions_mm);
// The criteria of `pattern` (a design of these options) and whether they meet the options.
DesignMetrics EvaluateDesign(const Pattern& pattern, const DesignOptions& options);

struct DesignStart {
  int start = 0;              // 0 .. starts - 1
  bool from_options = false;  // start 0 taken from options.start_mm
  DesignMetrics initial;      // of the start layout
  DesignMetrics final;        // of the layout the local search ended at (rounded to 1e-3 mm)
  int evaluations = 0;
  int nlopt_result = 0;  // nlopt_result code of the local run
};

struct DesignResult {
  DesignOptions options;
  // The best feasible layout by the objective (ties: the lower start), rotated so that the
  // centroid lies on the -x axis (the front carries the spread, like the SSL standard), ID patches
  // sorted by angle, positions rounded to 1e-3 mm; its metrics are of what is written.
  Pattern pattern;
  DesignMetrics metrics;
  int best_start = 0;
  std::vector<DesignStart> starts;
  int64_t evaluations = 0;  // layouts evaluated in all
  double seconds = 0.0;     // wall time of the search
  double evaluations_per_second = 0.0;
};

// Searches (see above). Throws InputError from Validate, or when no start ends feasible: naming
// the geometric constraints when no layout fits, else the criterion limit that no layout met
// with the best value found.
DesignResult RunDesign(const DesignOptions& options);

// The pattern file of the design (patterns/README.md format, loadable by every command), with a
// comment header giving the options and the metrics.
std::string DesignPatternFileText(const DesignResult& result);
// The report for people: options, the design's metrics, every start's outcome and the speed.
std::string DesignReportText(const DesignResult& result);

}  // namespace patlab::design

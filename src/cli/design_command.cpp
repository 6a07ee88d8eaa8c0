// patlab design: search patch layouts for a better pattern (design/design.h searches and renders).
#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "cli/text_output.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/design.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/atomic_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kDesignExamples = R"(examples:
  patlab design --out results/design                  # SSL robot top: 4 dots, 2 colours
  patlab design --min-rotation-onset-mm 3.5 --start ssl-standard --name ssl-designed --out d
  patlab design --objective rotation_onset --max-angle-crlb-mrad-per-mm 7.76 --out d
  patlab design --id-patches 3 --id-radii-mm 20 --palette 3 --outer-diameter-mm 150 --out d
  patlab design --symmetry mirror --objective rotation_onset --out d   # mirror-symmetric layouts
  patlab design --constraints ssl.toml --starts 8 --out d   # the file's options, --starts overridden

The key patch sits at the origin; the search moves the ID patches to minimise --objective
(angle_crlb, position_crlb or rotation_onset) subject to: every patch inside
--outer-diameter-mm less --rim-gap-mm, every two patches --min-gap-mm apart, at least --min-ids
IDs with --palette colours (0: every colouring), a rotation onset of at least
--min-rotation-onset-mm, and the CRLB limits. Messages name the options as the library spells
them (outer_diameter_mm for --outer-diameter-mm). docs/design.md defines every criterion.
Writes DIR/<name>.toml (a pattern file for patlab compare and every other command) and
DIR/<name>.design.txt (the report); the same options give byte-identical files.
Exit status: 0 ok, 1 cannot write --out, 2 bad input or impossible constraints (nothing written).
)";

struct DesignFlags {
  std::string constraints;
  std::string id_radii = "20";
  std::string objective = "angle_crlb";
  std::string symmetry = "none";
  std::string seed = "1";
  std::string start;
  std::string out_dir;
  std::string patterns_dir;
  bool quiet = false;
};

// The ID patch positions of a pattern file, as the first start.
std::vector<Vec2> StartLayout(const std::string& reference, const std::string& patterns_dir) {
  const std::string file = FindPattern(reference, patterns_dir);
  const Pattern pattern = formats::LoadPatternFile(file);
  std::vector<Vec2> layout;
  const Vec2 key = pattern.patches[pattern.key_index].position_mm;
  for (int slot : detect::IdSlots(pattern)) {
    layout.push_back(pattern.patches[slot].position_mm - key);
  }
  return layout;
}

// The options a flag sets, copied from the flags' values onto the constraints file's (or the
// defaults) when the flag is given: flags override the file.
using Copy = void (*)(const design::DesignOptions& from, design::DesignOptions* to);
struct FlagField {
  const char* flag;
  Copy copy;
};
constexpr FlagField kFlagFields[] = {
    {"name", [](const design::DesignOptions& f, design::DesignOptions* t) { t->name = f.name; }},
    {"outer-diameter-mm",
     [](const design::DesignOptions& f, design::DesignOptions* t) {
       t->outer_diameter_mm = f.outer_diameter_mm;
     }},
    {"rim-gap-mm", [](const design::DesignOptions& f,
                      design::DesignOptions* t) { t->rim_gap_mm = f.rim_gap_mm; }},
    {"key-radius-mm", [](const design::DesignOptions& f,
                         design::DesignOptions* t) { t->key_radius_mm = f.key_radius_mm; }},
    {"id-patches", [](const design::DesignOptions& f,
                      design::DesignOptions* t) { t->id_patches = f.id_patches; }},
    {"id-radii-mm", [](const design::DesignOptions& f,
                       design::DesignOptions* t) { t->id_radii_mm = f.id_radii_mm; }},
    {"min-gap-mm", [](const design::DesignOptions& f,
                      design::DesignOptions* t) { t->min_gap_mm = f.min_gap_mm; }},
    {"palette",
     [](const design::DesignOptions& f, design::DesignOptions* t) { t->palette = f.palette; }},
    {"tolerance-mm", [](const design::DesignOptions& f,
                        design::DesignOptions* t) { t->tolerance_mm = f.tolerance_mm; }},
    {"objective",
     [](const design::DesignOptions& f, design::DesignOptions* t) { t->objective = f.objective; }},
    {"symmetry",
     [](const design::DesignOptions& f, design::DesignOptions* t) { t->symmetry = f.symmetry; }},
    {"min-ids",
     [](const design::DesignOptions& f, design::DesignOptions* t) { t->min_ids = f.min_ids; }},
    {"min-rotation-onset-mm",
     [](const design::DesignOptions& f, design::DesignOptions* t) {
       t->min_rotation_onset_mm = f.min_rotation_onset_mm;
     }},
    {"max-angle-crlb-mrad-per-mm",
     [](const design::DesignOptions& f, design::DesignOptions* t) {
       t->max_angle_crlb_mrad_per_mm = f.max_angle_crlb_mrad_per_mm;
     }},
    {"max-position-crlb-per-mm",
     [](const design::DesignOptions& f, design::DesignOptions* t) {
       t->max_position_crlb_per_mm = f.max_position_crlb_per_mm;
     }},
    {"starts",
     [](const design::DesignOptions& f, design::DesignOptions* t) { t->starts = f.starts; }},
    {"max-evaluations", [](const design::DesignOptions& f,
                           design::DesignOptions* t) { t->max_evaluations = f.max_evaluations; }},
    {"seed", [](const design::DesignOptions& f, design::DesignOptions* t) { t->seed = f.seed; }},
};

design::DesignOptions ParseDesignOptions(const DesignFlags& f, design::DesignOptions flags,
                                         const po::variables_map& vm) {
  if (f.out_dir.empty()) throw InputError("missing --out DIR; expected the directory to write");
  const auto given = [&vm](const char* flag) { return vm.count(flag) && !vm[flag].defaulted(); };
  if (given("id-radii-mm")) {
    flags.id_radii_mm = ParseNumberList(f.id_radii, "--id-radii-mm",
                                        "radii in mm, one for every ID patch or one per ID patch");
  }
  if (given("objective"))
    flags.objective = ParseName(f.objective, design::kDesignObjectiveNames, "--objective");
  if (given("symmetry"))
    flags.symmetry = ParseName(f.symmetry, design::kDesignSymmetryNames, "--symmetry");
  if (given("seed")) flags.seed = ParseSeed(f.seed, "--seed");
  design::DesignOptions o = f.constraints.empty()
                                ? design::DesignOptions{}
                                : design::LoadDesignConstraints(f.constraints, {});
  for (const FlagField& field : kFlagFields) {
    if (given(field.flag)) field.copy(flags, &o);
  }
  if (!f.start.empty()) {
    o.start_mm = StartLayout(f.start, f.patterns_dir);
    if (o.start_mm.size() != static_cast<size_t>(o.id_patches)) {
      throw InputError("--start " + f.start + " has " + std::to_string(o.start_mm.size()) +
                       " ID patches; expected a pattern with id_patches (" +
                       std::to_string(o.id_patches) + ") ID patches");
    }
  }
  design::Validate(o);
  return o;
}

void AddDesignFlags(po::options_description* d, DesignFlags* f, design::DesignOptions* o) {
  // clang-format off
  d->add_options()
      ("constraints", po::value(&f->constraints),
       "a TOML file of the options below (docs/file-formats.md); flags given override it")
      ("name", po::value(&o->name)->default_value(o->name), "the designed pattern's name")
      ("outer-diameter-mm", po::value(&o->outer_diameter_mm)->default_value(o->outer_diameter_mm),
       "robot top diameter (mm)")
      ("rim-gap-mm", po::value(&o->rim_gap_mm)->default_value(o->rim_gap_mm),
       "smallest gap between a patch and the rim (mm)")
      ("key-radius-mm", po::value(&o->key_radius_mm)->default_value(o->key_radius_mm),
       "key patch radius (mm)")
      ("id-patches", po::value(&o->id_patches)->default_value(o->id_patches), "ID patches")
      ("id-radii-mm", po::value(&f->id_radii)->default_value(f->id_radii),
       "ID patch radius (mm), or one per ID patch, comma-separated")
      ("min-gap-mm", po::value(&o->min_gap_mm)->default_value(o->min_gap_mm),
       "smallest edge-to-edge gap between two patches (mm)")
      ("palette", po::value(&o->palette)->default_value(o->palette), "ID colours, 2..8")
      ("tolerance-mm", po::value(&o->tolerance_mm)->default_value(o->tolerance_mm),
       "symmetry tolerance of the ID count (mm; patlab ids)")
      ("objective", po::value(&f->objective)->default_value(f->objective),
       "what to minimise: angle_crlb, position_crlb or rotation_onset (maximised)")
      ("symmetry", po::value(&f->symmetry)->default_value(f->symmetry),
       "layout family searched: none, mirror (about the front-back axis) or cyclic")
      ("min-ids", po::value(&o->min_ids)->default_value(o->min_ids),
       "IDs required with --palette colours (0: every colouring)")
      ("min-rotation-onset-mm", po::value(&o->min_rotation_onset_mm)->default_value(o->min_rotation_onset_mm),
       "rotation onset required (mm of patch sigma)")
      ("max-angle-crlb-mrad-per-mm", po::value(&o->max_angle_crlb_mrad_per_mm),
       "angle CRLB allowed (mrad per mm of sigma; default none)")
      ("max-position-crlb-per-mm", po::value(&o->max_position_crlb_per_mm),
       "position CRLB allowed (mm per mm of sigma, per axis; default none)")
      ("starts", po::value(&o->starts)->default_value(o->starts), "seeded local searches")
      ("max-evaluations", po::value(&o->max_evaluations)->default_value(o->max_evaluations),
       "layouts evaluated per local search at most")
      ("seed", po::value(&f->seed)->default_value(f->seed), "seed of the random starts (integer >= 0)")
      ("start", po::value(&f->start), "a pattern file or name whose ID patches are the first start")
      ("out,o", po::value(&f->out_dir), "directory to write <name>.toml and <name>.design.txt to")
      ("quiet,q", po::bool_switch(&f->quiet), "no report on stdout, no progress or summary on stderr")
      ("patterns-dir", po::value(&f->patterns_dir),
       "a folder searched for pattern names before the shipped patterns")
      ("help,h", "show this help");
  // clang-format on
}

// The help's option groups (command_line.h).
const OptionGroups kDesignGroups = {
    {"robot top",
     {"constraints", "outer-diameter-mm", "rim-gap-mm", "key-radius-mm", "id-patches",
      "id-radii-mm", "min-gap-mm"}},
    {"IDs", {"palette", "tolerance-mm", "min-ids"}},
    {"objective and limits",
     {"objective", "symmetry", "min-rotation-onset-mm", "max-angle-crlb-mrad-per-mm",
      "max-position-crlb-per-mm"}},
    {"search", {"starts", "max-evaluations", "seed", "start", "patterns-dir"}},
    {"output", {"out", "name"}}};

int RunDesign(const std::vector<std::string>& args) {
  DesignFlags f;
  design::DesignOptions o;
  po::options_description visible("usage: patlab design [options] --out DIR\n\noptions");
  AddDesignFlags(&visible, &f, &o);
  po::variables_map vm;
  std::vector<std::string> none;
  if (!ParseArguments(args, visible, kDesignGroups, "positional", po::value(&none), 0,
                      kDesignExamples, &vm)) {
    return kExitOk;
  }
  o = ParseDesignOptions(f, o, vm);
  const std::filesystem::path dir(f.out_dir);
  io::CheckWritable({(dir / (o.name + ".toml")).string()});
  Progress progress("patlab design", "starts", !f.quiet, StderrIsTerminal());
  o.progress = progress.Callback();
  const design::DesignResult result = design::RunDesign(o);
  const std::string report = TrimLineEnds(design::DesignReportText(result));
  // A failure to write is an EnvironmentError: main() reports it, exit 1, nothing written.
  io::WriteFilesAtomic(
      {{(dir / (o.name + ".toml")).string(), design::DesignPatternFileText(result)},
       {(dir / (o.name + ".design.txt")).string(), report}});
  if (!f.quiet) std::cout << report;
  if (!f.quiet) {
    std::fputs(StringPrintf("patlab design: %lld layouts evaluated in %.2f s, %.0f evaluations/s\n",
                            static_cast<long long>(result.evaluations), result.seconds,
                            result.evaluations_per_second)
                   .c_str(),
               stderr);
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("design", "search patch layouts for a better pattern (NLopt COBYLA)",
                        RunDesign);

}  // namespace patlab::cli

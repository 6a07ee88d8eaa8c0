// patlab import: SSL-Vision pattern sheets -> pattern files and codebooks (design/sheet_import.h).
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/sheet_import.h"
#include "patlab/io/atomic_file.h"
#include "patlab/vision/frame_io.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kImportExamples = R"(examples:
  patlab import ../shared/frames/ssl-standard-pattern-2010-16ids.png --name ssl-standard --out /tmp/p
  patlab import sheets/*.png --out /tmp/designs           # every sheet, all or nothing

A SHEET is an SSL-Vision pattern sheet (PNG/JPEG/PPM): 200 px cells at 1 px = 1 mm, one robot
top per cell (ID = cell index, row-major), blue centre (key) patch, pink/green/cyan/white dots,
front up. Ring sectors instead of dots (the KIKS sheet) are split by angle and each modelled as a
disc patch at the sector's centroid (docs/import.md). Each distinct set of dot positions on a sheet becomes one pattern file
<name>.toml (or <name>-<k>.toml) with its codebook <name>.codebook.toml; a dot absent from a cell
makes that cell a different layout. IDs the symmetry rule (patlab ids) makes confusable with an
earlier ID of the layout are left out and named in the codebook's header and on stdout.
Exit status: 0 ok, 1 cannot write, 2 bad input (nothing is written).
)";

struct ImportFlags {
  std::vector<std::string> sheets;
  std::string out_dir = ".";
  std::string name;
  design::SheetImportOptions options;
};

std::string Summary(const design::SheetImport& sheet) {
  const bool sectors = !sheet.sector_bounds_deg.empty();
  std::string out = sheet.file + ": " + std::to_string(sheet.cells.size()) + " cells of " +
                    std::to_string(sheet.columns * sheet.rows) + ", " +
                    std::to_string(sheet.slots.size()) +
                    (sectors ? " ring sectors (as disc patches), " : " dot positions, ") +
                    std::to_string(sheet.layouts.size()) +
                    (sheet.layouts.size() == 1 ? " layout\n" : " layouts\n");
  for (const design::ImportedLayout& l : sheet.layouts) {
    out += "  " + l.pattern.name + ": " + std::to_string(l.pattern.size() - 1) +
           (sectors ? " sectors, " : " dots, ") + std::to_string(l.codebook.entries.size()) +
           " IDs";
    if (l.codebook.entries.empty()) out += " (no codebook written)";
    for (const auto& [id, why] : l.dropped) {
      out += "; ID " + std::to_string(id) + " left out: " + why;
    }
    out += "\n";
  }
  return out;
}

// The help's option groups (command_line.h).
const OptionGroups kImportGroups = {{"sheet", {"cell-px", "mm-per-px", "slot-tolerance"}},
                                    {"IDs", {"tolerance"}},
                                    {"output", {"out", "name"}}};

int RunImport(const std::vector<std::string>& args) {
  ImportFlags f;
  po::options_description visible("usage: patlab import SHEET... [options]\n\noptions");
  // clang-format off
  visible.add_options()
      ("out,o", po::value(&f.out_dir)->default_value(f.out_dir), "directory for the pattern files, made if missing")
      ("name", po::value(&f.name), "pattern name (one SHEET only; default: the file's stem)")
      ("cell-px", po::value(&f.options.cell_px)->default_value(f.options.cell_px), "cell size (px)")
      ("mm-per-px", po::value(&f.options.mm_per_px)->default_value(f.options.mm_per_px), "scale")
      ("slot-tolerance", po::value(&f.options.slot_tolerance_mm)->default_value(f.options.slot_tolerance_mm),
       "dots of two cells closer than this (mm) are one slot")
      ("tolerance", po::value(&f.options.symmetry_tolerance_mm)->default_value(f.options.symmetry_tolerance_mm),
       "symmetry tolerance (mm) of the codebook check (patlab ids)")
      ("help,h", "show this help");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kImportGroups, "sheet", po::value(&f.sheets), -1,
                      kImportExamples, &vm)) {
    return kExitOk;
  }
  if (f.sheets.empty()) {
    throw InputError("missing SHEET; expected 'patlab import SHEET... [--out DIR]' (see --help)");
  }
  if (!f.name.empty() && f.sheets.size() > 1) {
    throw InputError("--name with " + std::to_string(f.sheets.size()) +
                     " sheets; expected one SHEET with --name");
  }
  f.options.name = f.name;
  // Every sheet is read and imported before anything is written.
  std::vector<std::pair<std::string, std::string>> files;
  std::string summary;
  for (const std::string& path : f.sheets) {
    const design::SheetImport sheet = design::ImportSheet(vision::ReadFrame(path), path, f.options);
    summary += Summary(sheet);
    for (const design::ImportedLayout& l : sheet.layouts) {
      const std::filesystem::path dir(f.out_dir);
      files.emplace_back((dir / (l.pattern.name + ".toml")).string(),
                         design::PatternFileText(l, sheet));
      // A layout whose every colouring the symmetry rule rejects has no codebook to write.
      if (!l.codebook.entries.empty()) {
        files.emplace_back((dir / (l.pattern.name + ".codebook.toml")).string(),
                           design::CodebookFileText(l, sheet));
      }
    }
  }
  for (size_t a = 0; a < files.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      if (files[a].first == files[b].first) {
        throw InputError(files[a].first +
                         " would be written twice; expected sheets with "
                         "distinct names");
      }
    }
  }
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& error) {
    std::cerr << "patlab import: " << error.what() << "\n";
    return kExitFailure;
  }
  std::cout << summary;
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("import", "pattern sheets (PNG) -> pattern files and codebooks", RunImport);

}  // namespace patlab::cli

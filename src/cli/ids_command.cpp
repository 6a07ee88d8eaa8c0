// patlab ids: the paper's Table II for any patterns -- how many IDs a pattern can carry with n
// ID colours, once its rotational symmetry (found from its geometry) is taken into account.
#include <boost/program_options.hpp>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/text_output.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/detect/codebook.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/toml_util.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kIdsExamples = R"(examples:
  patlab ids simple linear triangle butterfly              # Table II (2, 3, 4 colours)
  patlab ids ssl-standard --colors 2 --list                # the 16 colourings, slot by slot
  patlab ids butterfly --colors 2,3 --tolerance 30         # a tolerance past its asymmetry
  patlab ids my-pattern.toml --colors 1,2,3,4,5

A PATTERN is a pattern file or the name of a shipped pattern (or one in --patterns-dir). Counting rule: a rotation about
the key patch that maps every patch to within --tolerance mm of another cannot be decided by
geometry, nor can any composition of such rotations (the group they generate); a colouring of
the ID slots is an ID only if no rotation of that group maps it onto itself, and colourings the
group maps onto each other are one ID. The table after the counts says, per rotation, its
residual (worst patch distance) against the tolerance and what decides it. With --list, colours are letters A, B,
... and each ID lists one colour per ID slot in the pattern file's patch order. Exit status: 0
ok, 2 bad input.
)";

struct IdsOptions {
  std::vector<std::string> patterns;
  std::string colors = "2,3,4";
  double tolerance_mm = 10.0;
  bool list = false;
  std::string patterns_dir;
};

struct Row {
  Pattern pattern;
  detect::Symmetry symmetry;
};

// Table II: one row per pattern, one column per palette size.
std::string IdsTable(const std::vector<Row>& rows, const std::vector<int>& colours,
                     double tolerance_mm) {
  std::ostringstream out;
  out << "IDs per ID palette size (paper Table II; key patch and key colour excluded), symmetry "
         "tolerance "
      << FormatNumber(tolerance_mm) << " mm\n\n";
  size_t name_width = 7;
  for (const Row& r : rows) name_width = std::max(name_width, r.pattern.name.size());
  out << std::left << std::setw(static_cast<int>(name_width) + 2) << "pattern" << std::setw(7)
      << "slots" << std::setw(11) << "rotations";
  for (int n : colours)
    out << std::setw(12) << (std::to_string(n) + (n == 1 ? " colour" : " colours"));
  out << "\n";
  for (const Row& r : rows) {
    out << std::setw(static_cast<int>(name_width) + 2) << r.pattern.name << std::setw(7)
        << detect::IdSlots(r.pattern).size() << std::setw(11) << r.symmetry.effective_order();
    for (int n : colours) out << std::setw(12) << detect::CountIds(r.pattern, r.symmetry, n);
    out << "\n";
  }
  out << "\nrotations: rotations about the key that geometry cannot tell apart and ID colours "
         "must decide\n";
  for (const Row& r : rows) {
    out << "\n"
        << r.pattern.name << ": " << detect::SymmetrySummary(r.symmetry) << "\n"
        << detect::SymmetryTable(r.symmetry, "  ");
  }
  return out.str();
}

// --list: every ID's colours (letters A, B, ...) slot by slot, per pattern and palette size.
std::string IdLists(const std::vector<Row>& rows, const std::vector<int>& colours) {
  std::ostringstream out;
  for (const Row& r : rows) {
    for (int n : colours) {
      std::vector<std::string> names;
      for (int c = 0; c < n; ++c) names.emplace_back(1, static_cast<char>('A' + c));
      const detect::Codebook book = detect::GenerateCodebook(r.pattern, r.symmetry, names);
      out << "\n"
          << r.pattern.name << ", " << n << (n == 1 ? " colour" : " colours") << ": "
          << book.entries.size() << " IDs (slots = patches";
      for (int slot : detect::IdSlots(r.pattern)) out << " " << slot;
      out << ")\n";
      for (const detect::CodebookEntry& e : book.entries) {
        out << "  " << std::right << std::setw(4) << e.id << " " << std::left;
        for (int c : e.colour) out << " " << names[c];
        out << "\n";
      }
    }
  }
  return out.str();
}

// The help's option groups (command_line.h).
const OptionGroups kIdsGroups = {
    {"input", {"patterns-dir"}}, {"IDs", {"colors", "tolerance"}}, {"output", {"list"}}};

int RunIds(const std::vector<std::string>& args) {
  IdsOptions o;
  po::options_description visible("usage: patlab ids PATTERN... [options]\n\noptions");
  visible.add_options()("colors", po::value(&o.colors)->default_value(o.colors),
                        "ID palette sizes n (key colour excluded), comma-separated")(
      "tolerance", po::value(&o.tolerance_mm)->default_value(o.tolerance_mm),
      "distance (mm) below which two patch positions count as the same when finding the "
      "pattern's rotational symmetry (paper section III: 10 mm)")("list", po::bool_switch(&o.list),
                                                                  "also list every ID's colours")(
      "patterns-dir", po::value(&o.patterns_dir),
      "a folder searched for pattern names before the shipped patterns")("help,h",
                                                                         "show this help");
  po::variables_map vm;
  if (!ParseArguments(args, visible, kIdsGroups, "pattern", po::value(&o.patterns), -1,
                      kIdsExamples, &vm, {{"-c", "--colors"}})) {
    return kExitOk;
  }
  if (o.patterns.empty()) {
    throw InputError(
        "missing PATTERN; expected 'patlab ids PATTERN... [--colors 2,3,4]' (see --help)");
  }
  CheckTolerance(o.tolerance_mm);
  const std::vector<int> colours = ParseColourCounts(o.colors);
  if (o.list) {
    for (int n : colours) {
      if (n > 8) {
        throw InputError("--list with " + std::to_string(n) +
                         " colours; expected at most 8 colours when listing IDs");
      }
    }
  }
  std::vector<Row> rows;
  for (const std::string& reference : o.patterns) {
    Row row;
    row.pattern = formats::LoadPatternFile(FindPattern(reference, o.patterns_dir));
    row.symmetry = detect::FindSymmetry(row.pattern, o.tolerance_mm);
    rows.push_back(std::move(row));
  }
  std::cout << TrimLineEnds(IdsTable(rows, colours, o.tolerance_mm) +
                            (o.list ? IdLists(rows, colours) : std::string()));
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("ids", "Table II: how many IDs a pattern carries with n colours", RunIds);

}  // namespace patlab::cli

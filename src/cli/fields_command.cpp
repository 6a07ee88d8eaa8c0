// patlab fields: the shipped field models (formats/field_file.h ShippedFields, FieldFamily) --
// a list with one line each, a family's models newest first, or one model's landmarks, lines and
// arcs (calib/field.h FieldDescriptionText).
#include <boost/program_options.hpp>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/data.h"
#include "patlab/calib/field.h"
#include "patlab/core/error.h"
#include "patlab/formats/field_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kFieldsExamples = R"(examples:
  patlab fields                  # every shipped model and family, one line each
  patlab fields ssl              # the SSL models, newest first
  patlab fields ssl-div-b        # one model: its landmarks, lines and arcs (mm, degrees)
  patlab fields my-field.toml    # a field file of your own

Without NAME: the shipped field models (name, size between the lines' centres and the floor
beyond them, first year of the rules, source) and the families. NAME is a family (ssl, vss: its
models, newest first), a shipped model's name, or a field file; `patlab live --field` takes the
same names (docs/fields.md). Exit status: 0 ok, 2 bad input.
)";

std::string FamilyLines(const std::vector<calib::Field>& fields) {
  std::string out;
  for (const calib::Field& f : fields) out += calib::FieldSummaryLine(f) + "\n";
  return out;
}

int RunFields(const std::vector<std::string>& args) {
  std::string name;
  po::options_description visible("usage: patlab fields [NAME|FAMILY]");
  visible.add_options()("help,h", "show this help");
  po::variables_map vm;
  if (!ParseArguments(args, visible, OptionGroups{}, "name", po::value(&name), 1, kFieldsExamples,
                      &vm)) {
    return kExitOk;
  }
  const std::vector<std::string>& roots = DataRoots();
  if (name.empty()) {
    const std::vector<calib::Field> fields = formats::ShippedFields(roots);
    std::cout << "field models (name, size, first year of the rules, source):\n"
              << FamilyLines(fields) << "\nfamilies (models newest first):\n";
    for (const std::string& family : formats::FieldFamilies(roots)) {
      std::string names;
      for (const calib::Field& f : formats::FieldFamily(family, roots))
        names += (names.empty() ? "" : ", ") + f.name;
      std::cout << "  " << family << ": " << names << "\n";
    }
    return kExitOk;
  }
  if (const std::vector<calib::Field> family = formats::FieldFamily(name, roots); !family.empty()) {
    std::cout << "family " << name << " (newest first):\n" << FamilyLines(family);
    return kExitOk;
  }
  std::cout << calib::FieldDescriptionText(
      formats::LoadField(FindData(name, io::DataKind::kField)));
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("fields", "list the shipped field models, or print one's landmarks",
                        RunFields);

}  // namespace patlab::cli

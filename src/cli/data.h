// Shipped data found by name from the command line (io/data_path.h): main() sets the running
// binary's folder once; the commands resolve their arguments through FindData.
#pragma once

#include <string>
#include <vector>

#include "patlab/io/data_path.h"

namespace patlab::cli {

// The folder of the running binary (main() calls this first).
void SetBinaryDir(const std::string& dir);
// The data roots: $PATLAB_DATA, <binary>/../share/patlab, the build tree's source.
const std::vector<std::string>& DataRoots();
// `reference` as an existing file or a name of shipped data (InputError when neither).
std::string FindData(const std::string& reference, io::DataKind kind);
// A pattern: `reference` as a file, then <patterns_dir>/<reference>.toml when `patterns_dir` is
// given (--patterns-dir), then the shipped patterns.
std::string FindPattern(const std::string& reference, const std::string& patterns_dir);

}  // namespace patlab::cli

// Results are written atomically: to a temporary file in the target directory, then renamed, so
// a reader never sees a half-written results file and a failed run leaves the old one in place.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace patlab::io {

// Writes several files, creating missing parent directories; throws
// InputError("<path>: cannot write: <reason>") on failure. Each file is fully written to its
// temporary before any is renamed, so a failure while writing leaves every target untouched.
void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace patlab::io

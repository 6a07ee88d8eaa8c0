#include "cli/data.h"

#include <cstdlib>
#include <filesystem>

namespace patlab::cli {

namespace {
std::string& BinaryDir() {
  static std::string dir;
  return dir;
}
}  // namespace

void SetBinaryDir(const std::string& dir) { BinaryDir() = dir; }

const std::vector<std::string>& DataRoots() {
  static const std::vector<std::string> roots =
      io::DataRoots(BinaryDir(), std::getenv("PATLAB_DATA"));
  return roots;
}

// A found file under the working directory is named relative to it, as the user would have
// typed it ("patterns/butterfly.toml"): report and result files that name their inputs then read
// the same whether a name or a path was given.
std::string FindData(const std::string& reference, io::DataKind kind) {
  const std::string found = io::FindData(reference, kind, DataRoots());
  if (found == reference) return found;
  std::error_code ec;
  const std::filesystem::path relative =
      std::filesystem::path(found).lexically_relative(std::filesystem::current_path(ec));
  if (ec || relative.empty() || *relative.begin() == "..") return found;
  return relative.string();
}

std::string FindPattern(const std::string& reference, const std::string& patterns_dir) {
  if (!patterns_dir.empty()) {
    std::error_code ec;
    const std::filesystem::path candidate =
        std::filesystem::path(patterns_dir) / (reference + ".toml");
    if (!std::filesystem::exists(reference, ec) &&
        std::filesystem::is_regular_file(candidate, ec)) {
      return candidate.string();
    }
  }
  return FindData(reference, io::DataKind::kPattern);
}

}  // namespace patlab::cli

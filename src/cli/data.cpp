#include "cli/data.h"

#include <cstdlib>

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

std::string FindData(const std::string& reference, io::DataKind kind) {
  return io::FindData(reference, kind, DataRoots());
}

}  // namespace patlab::cli

#include "patlab/io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "patlab/core/error.h"

namespace patlab::io {

namespace {

std::string TempPath(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

void WriteTemp(const std::string& path, const std::string& temp, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  if (ec) throw InputError(path + ": cannot write: " + ec.message());
  FILE* f = std::fopen(temp.c_str(), "wb");
  if (f == nullptr) throw InputError(path + ": cannot write: " + std::strerror(errno));
  const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
                  std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const int saved_errno = errno;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(temp.c_str());
    throw InputError(path + ": cannot write: " + std::strerror(ok ? errno : saved_errno));
  }
}

void Rename(const std::string& temp, const std::string& path) {
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int saved_errno = errno;
    std::remove(temp.c_str());
    throw InputError(path + ": cannot write: " + std::strerror(saved_errno));
  }
}

}  // namespace

void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::string> temps;
  try {
    for (const auto& [path, content] : files) {
      temps.push_back(TempPath(path));
      WriteTemp(path, temps.back(), content);
    }
  } catch (...) {
    for (const std::string& t : temps) std::remove(t.c_str());
    throw;
  }
  for (size_t k = 0; k < files.size(); ++k) Rename(temps[k], files[k].first);
}

}  // namespace patlab::io

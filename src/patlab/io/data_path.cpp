#include "patlab/io/data_path.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "patlab/core/close_names.h"
#include "patlab/core/error.h"

namespace patlab::io {

namespace {

namespace fs = std::filesystem;

struct KindInfo {
  const char* name;
  std::vector<const char*> folders;
};

KindInfo Info(DataKind kind) {
  switch (kind) {
    case DataKind::kPattern:
      return {"pattern", {"patterns"}};
    case DataKind::kExperiment:
      return {"experiment", {"experiments", "experiments/camera-noise"}};
    case DataKind::kSettings:
      return {"settings file", {"settings", "experiments", "experiments/camera-noise"}};
    case DataKind::kField:
      return {"field", {"experiments/fields"}};
  }
  return {"file", {}};
}

bool IsDirectory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// patlab_SOURCE_DIR from a build tree's CMakeCache.txt, or "" when there is none.
std::string SourceDirOfBuildTree(const fs::path& binary_dir) {
  std::ifstream cache(binary_dir / "CMakeCache.txt");
  const std::string key = "patlab_SOURCE_DIR:STATIC=";
  for (std::string line; std::getline(cache, line);) {
    if (line.starts_with(key)) return line.substr(key.size());
  }
  return "";
}

void AddRoot(const fs::path& root, std::vector<std::string>* roots) {
  if (root.empty() || !IsDirectory(root)) return;
  std::error_code ec;
  const std::string text = fs::weakly_canonical(root, ec).string();
  if (ec) return;
  if (std::find(roots->begin(), roots->end(), text) == roots->end()) roots->push_back(text);
}

}  // namespace

std::vector<std::string> DataRoots(const std::string& binary_dir, const char* env_value) {
  std::vector<std::string> roots;
  if (env_value != nullptr && *env_value != '\0') AddRoot(env_value, &roots);
  if (!binary_dir.empty()) {
    AddRoot(fs::path(binary_dir) / ".." / "share" / "patlab", &roots);
    AddRoot(SourceDirOfBuildTree(binary_dir), &roots);
  }
  return roots;
}

std::vector<std::string> DataNames(DataKind kind, const std::vector<std::string>& roots) {
  std::vector<std::string> names;
  for (const std::string& root : roots) {
    for (const char* folder : Info(kind).folders) {
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(fs::path(root) / folder, ec)) {
        const fs::path& p = entry.path();
        if (p.extension() != ".toml" || !IsFile(p)) continue;
        names.push_back(p.stem().string());
      }
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

std::string FindData(const std::string& reference, DataKind kind,
                     const std::vector<std::string>& roots) {
  // A path (with a folder) is the caller's to open: its loader says when it is missing.
  std::error_code ec;
  (void)fs::exists(reference, ec);
  ThrowIfPathUnusable(reference, ec);  // too long, a symbolic link loop: said as such
  if (IsFile(reference) || reference.find('/') != std::string::npos) return reference;
  const KindInfo info = Info(kind);
  std::string searched;
  for (const std::string& root : roots) {
    for (const char* folder : info.folders) {
      const fs::path dir = fs::path(root) / folder;
      if (!IsDirectory(dir)) continue;
      searched += (searched.empty() ? "" : ", ") + dir.string() + "/";
      for (const std::string& candidate : {reference, reference + ".toml"}) {
        if (IsFile(dir / candidate)) return (dir / candidate).string();
      }
    }
  }
  std::string message =
      std::string(info.name) + " '" + EscapeForMessage(reference) +
      "' not found; expected an existing file or a name in " +
      (searched.empty() ? "a data folder (none found: set PATLAB_DATA)" : searched);
  const std::vector<std::string> close = CloseNames(reference, DataNames(kind, roots));
  if (!close.empty()) message += " (did you mean " + QuotedAlternatives(close) + "?)";
  throw InputError(message);
}

}  // namespace patlab::io

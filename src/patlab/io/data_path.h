// Shipped data found by name: `patlab simulate fig5`, `patlab evaluate butterfly`,
// `patlab detect ... --settings ssl-frame`. A reference that is an existing path is that path;
// any other is looked up, by kind, in the data roots: $PATLAB_DATA (when set), the installed
// share/patlab beside the running binary (<prefix>/bin/../share/patlab), and, for a binary in a
// build tree, the source tree it was configured from. The binary's location is the caller's to
// give (the CLI passes its own; a Python module would pass its package's), so nothing here reads
// the process's state but the files it is asked about.
#pragma once

#include <string>
#include <vector>

namespace patlab::io {

// What a name refers to; each kind has its folders under a data root (docs/cli.md):
//   pattern     patterns/<name>.toml
//   experiment  experiments/<name>.toml (and experiments/camera-noise/)
//   settings    settings/<name>.toml, then experiments/<name>.toml (detector settings, scenes,
//               thresholds, calibrations, calibration inputs, labels)
//   field       experiments/fields/<name>.toml
enum class DataKind { kPattern, kExperiment, kSettings, kField };

// The data roots in search order, each an existing directory: `env_value` ($PATLAB_DATA; null
// or empty: none), `binary_dir`/../share/patlab, and the source tree named by
// `binary_dir`/CMakeCache.txt (patlab_SOURCE_DIR) when the binary is in a build tree.
std::vector<std::string> DataRoots(const std::string& binary_dir, const char* env_value);

// `reference` when it names an existing file or has a folder in it (a path: its loader reports
// a missing file); else the first <root>/<folder>/<reference> or
// <reference>.toml of the kind's folders. Throws InputError when there is none: "<kind>
// '<name>' not found; expected a file path or a name in <folders searched>", with the close
// names of the shipped data of that kind ("did you mean 'butterfly'?").
std::string FindData(const std::string& reference, DataKind kind,
                     const std::vector<std::string>& roots);

// The names of the shipped data of one kind (file stems, sorted), for messages and completion.
std::vector<std::string> DataNames(DataKind kind, const std::vector<std::string>& roots);

}  // namespace patlab::io

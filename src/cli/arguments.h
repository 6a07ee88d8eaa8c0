// Argument handling shared by the subcommands: one way to parse flags plus positional
// arguments, print --help, and read the list, seed and thread-count values every command takes.
// Every problem is an InputError naming the flag and what was expected (exit status 2).
#pragma once

#include <boost/program_options.hpp>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cli/command_line.h"
#include "patlab/core/options.h"
#include "patlab/render/camera_render.h"

namespace patlab::cli {

// Parses `args` against the `visible` options, printed in the named `groups` (command_line.h), plus
// positional arguments stored through `positional` under the hidden option `positional_name` (at
// most `max_positional`; -1 = any number). With --help (which `visible` must define), prints the
// options and `examples` on stdout and returns false: the command then exits 0. Throws
// boost::program_options::error on bad flags.
bool ParseArguments(const std::vector<std::string>& args,
                    const boost::program_options::options_description& visible,
                    const OptionGroups& groups, const char* positional_name,
                    boost::program_options::value_semantic* positional, int max_positional,
                    const char* examples, boost::program_options::variables_map* vm,
                    const std::vector<std::pair<std::string, std::string>>& removed = {});

// A comma-separated list of numbers: "--sigmas has 'x'; expected <expected>".
std::vector<double> ParseNumberList(const std::string& text, const std::string& flag,
                                    const std::string& expected);
// A comma-separated list of integers in [lo, hi]: "--colors has '0'; expected <expected>".
std::vector<int> ParseIntegerList(const std::string& text, const std::string& flag, int lo, int hi,
                                  const std::string& expected);
// An unsigned 64-bit seed: "--seed is '-4'; expected an integer >= 0".
uint64_t ParseSeed(const std::string& text, const std::string& flag);
// "--threads is -1; expected 0 (all cores) to 4096" (sim::kMaxThreads).
void CheckThreads(int threads);
// The symmetry tolerance of `patlab ids` and `patlab evaluate`: a distance in mm >= 0.
void CheckTolerance(double tolerance_mm);
// The first problem of a library options check (`problems`, from Check(options)) about a value a
// flag set, thrown with the flag's name in place of the option's: `names` pairs each option name
// as the message starts with it (e.g. "min_area_px") with its flag ("--min-area-px"). A problem
// about a value no flag of `vm` set is left to the library (it names its file and key).
void ThrowFlagProblem(const std::vector<OptionsProblem>& problems,
                      const boost::program_options::variables_map& vm,
                      const std::vector<std::pair<std::string, std::string>>& names);
// The colour camera's flags of `patlab render` and `patlab camtrack` (sensor and jitter), each
// problem naming its flag (ThrowFlagProblem).
void ThrowCameraFlagProblem(const render::CameraSensorOptions& sensor,
                            const render::CameraJitter& jitter,
                            const boost::program_options::variables_map& vm);
// The ID palette sizes of `patlab ids` and `patlab evaluate` (--colors): integers 1..16.
std::vector<int> ParseColourCounts(const std::string& text);

}  // namespace patlab::cli

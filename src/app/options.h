// What the subcommands share about their options: checks that refuse a value before any work
// (NaN and infinities included), sizes, numbers passed on as scene keys, and the exit codes
// their --help lists.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace drape::app {

/// Accepts a finite number in [lo, hi] (CLI::Range lets NaN through: every comparison with it
/// is false).
CLI::Validator finite_range(double lo, double hi);

/// Refuses the empty string, which would otherwise mean "not given" and be ignored.
extern const CLI::Validator kNonEmpty;

/// Parses "WxH" (e.g. "960x540"); throws InputError naming `option` when it is not a size in
/// [16, 8192]².
void parse_size(const std::string& option, const std::string& text, int& width, int& height);

/// `x` as JSON text that reads back as the same double (std::to_string keeps six decimals, so
/// --seconds 1e-9 became 0).
std::string exact_number(double x);

/// Throws InputError when `output` is the scene file itself (the same file by any name), which
/// writing would destroy.
void check_not_the_scene(const std::string& option, const std::string& output,
                         const std::string& scene);

/// Adds --threads N (in [1, 1024]; default: every core) to `cmd`, stored in `threads` (0: not
/// given).
void add_threads_option(CLI::App* cmd, int& threads);
/// Has the parallel loops the calling thread opens use `threads` threads (0: the default).
/// OpenMP keeps the count per thread: a thread of a command's own calls this itself.
void use_threads(int threads);

/// The --help footer listing what each of `codes` means (codes from commands.h).
std::string exit_codes_help(const std::vector<int>& codes);

}  // namespace drape::app

// The `drape` subcommands. Each registers its options on the CLI11 app and returns the exit
// code: 0 success, 2 bad input, 3 diverged, 130/143 interrupted.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace drape::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitDiverged = 3;

/// Registers `drape run`; the returned function runs it after parsing.
std::function<int()> add_run_command(CLI::App& app);

/// Registers `drape compare`: one scene with each method, a table side by side.
std::function<int()> add_compare_command(CLI::App& app);

/// The shipped scenes' folder: $DRAPE_SCENES, else ./scenes, else the source tree's.
std::string scenes_dir();

}  // namespace drape::app

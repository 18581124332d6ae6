// The `drape` subcommands. Each registers its options on the CLI11 app and returns the exit
// code: 0 success, 2 bad input, 3 diverged, 4 no display or OpenGL, 5 an output could not be
// written, 129/130/143 interrupted (the README's table says which command returns which).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace drape::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitDiverged = 3;
/// No display (drape view) or no EGL/OpenGL context (drape render) could be had.
inline constexpr int kExitNoGraphics = 4;
/// The work was done (its summary printed) but an output could not be written: a full disk, a
/// folder removed during the run, a pipe whose reader left. Checked before the work as far as
/// it can be, where it is exit 2.
inline constexpr int kExitOutputFailed = 5;

/// Each registers a subcommand; the returned function runs it if it was given (else -1).
std::function<int()> add_run_command(CLI::App& app);
std::function<int()> add_bench_command(CLI::App& app);
std::function<int()> add_mesh_command(CLI::App& app);
/// Registers `drape lab cantilever` and `drape lab cusick`: textile tests of a material.
std::function<int()> add_lab_command(CLI::App& app);

/// Registers `drape render` (frames to PNG without a display, through EGL).
std::function<int()> add_render_command(CLI::App& app);

/// Registers `drape compare`: one scene with each method, a table side by side.
std::function<int()> add_compare_command(CLI::App& app);

/// Registers `drape view` (the interactive viewer).
std::function<int()> add_view_command(CLI::App& app);

/// A data folder shipped with drape ("scenes", "bench"): $DRAPE_SCENES or $DRAPE_BENCH, else
/// the folder of that name in the working directory, else the source tree's.
std::string data_dir(const std::string& name);
inline std::string scenes_dir() { return data_dir("scenes"); }

}  // namespace drape::app

// The `drape` subcommands. Each registers its options on the CLI11 app and returns the exit
// code: 0 success, 2 bad input, 3 diverged, 4 no display or OpenGL, 130/143 interrupted.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace drape::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitDiverged = 3;
/// No display (drape view) or no EGL/OpenGL context (drape render) could be had.
inline constexpr int kExitNoGraphics = 4;

/// Registers `drape run`; the returned function runs it after parsing.
std::function<int()> add_run_command(CLI::App& app);

/// Registers `drape render` (frames to PNG without a display, through EGL).
std::function<int()> add_render_command(CLI::App& app);

/// Registers `drape view` (the interactive viewer).
std::function<int()> add_view_command(CLI::App& app);

/// Parses "WxH" (e.g. "960x540"); throws InputError naming `option` when it is not a size in
/// [16, 8192]².
void parse_size(const std::string& option, const std::string& text, int& width, int& height);

/// The shipped scenes' folder: $DRAPE_SCENES, else ./scenes, else the source tree's.
std::string scenes_dir();

}  // namespace drape::app

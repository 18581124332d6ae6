// Runs a simulation for a number of frames, timing each, watching for divergence and
// interrupts; shared by `drape run` and the commands that build on it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/simulation.h"

namespace drape::app {

/// How a run ended: all its frames, diverged, stopped by a signal, or stopped because an output
/// written during it (an exported frame, a picture) could not be written.
enum class RunStatus { ok, diverged, interrupted, output_failed };
const char* to_string(RunStatus s);

struct RunResult {
  RunStatus status = RunStatus::ok;
  int64_t frames = 0;             ///< frames simulated
  double wall_seconds = 0.0;      ///< whole loop, exports included
  double setup_ms = 0.0;          ///< building the simulation
  std::vector<double> frame_ms;   ///< wall time of each frame's step alone
  int signal = 0;                 ///< the signal that interrupted the run, or 0
  std::string output_error;       ///< why an output failed (status output_failed), else empty
  double median_ms() const;
};

struct RunHooks {
  /// Called after each frame (and once before the first, with frame() == 0). May throw; an
  /// io::OutputError stops the run with status output_failed.
  std::function<void(const Simulation&)> after_frame;
  /// Text after the progress bar; empty: no bar.
  std::string progress_label;
};

/// Steps `sim` until `frames` frames are done, it diverges, or SIGINT/SIGTERM arrives (the
/// frame under way is finished first).
RunResult run_frames(Simulation& sim, int64_t frames, const RunHooks& hooks);

/// What a command may spend unless --force is given: memory for the cloth, and work for the
/// run. Both protect a shared machine from a typo (resolution [20000, 20000], dt = 1e-6 s for a
/// day) that would otherwise swap or run for hours.
struct Budget {
  int64_t bytes = int64_t{2} << 30;  ///< estimated memory of state, springs and solver
  double updates = 3e11;  ///< frames × substeps × (particles + springs): about an hour at 10 ns
};

/// Throws InputError (at cloth.resolution) if the cloth would not fit the budget.
void check_memory(const SceneDef& def, const Budget& budget = {});

/// Throws InputError (at `option`, e.g. "--size 8192x8192") if a picture of `picture_bytes`
/// (render::estimated_picture_bytes) and the cloth together would not fit the budget.
void check_memory(const SceneDef& def, int64_t picture_bytes, const std::string& option,
                  const Budget& budget = {});
/// Throws InputError (at duration) if `frames` frames of `sim` would exceed the budget.
void check_work(const Simulation& sim, int64_t frames, const Budget& budget = {});

/// The exit code for a finished run: 0, 3 (diverged: reported with the frame, the reason and a
/// hint), 129/130/143 (interrupted: reported with the frame and what was kept, `kept`) or 5 (an
/// output failed during the run: reported with the frame).
int exit_code(const std::string& scene, const Simulation& sim, const RunResult& run,
              const char* kept);

/// A figure for JSON, which has no infinities or NaN: the number when finite, else the string
/// "inf", "-inf" or "nan" (never null, so a reader sees what went wrong).
nlohmann::json figure(double x);

/// The stats other tools read (keys documented in the README).
nlohmann::json stats_json(const Simulation& sim, const RunResult& run);

/// JSON text as drape writes it: indented, and any invalid UTF-8 in strings (a name set with
/// --set can hold any bytes) replaced rather than thrown on.
std::string json_text(const nlohmann::json& j);

}  // namespace drape::app

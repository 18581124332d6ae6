// Runs a simulation for a number of frames, timing each, watching for divergence and
// interrupts; shared by `drape run` and the commands that build on it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "drape/simulation.h"
#include "io/run_stats.h"

namespace drape::app {

// The run's record and its stats live with the stats writer, which the Python module shares.
using io::RunResult;
using io::RunStatus;
using io::figure;
using io::json_text;
using io::stats_json;

struct RunHooks {
  /// Called after each frame (and once before the first, with frame() == 0). May throw; an
  /// io::OutputError stops the run with status output_failed.
  std::function<void(const Simulation&)> after_frame;
  /// Text after the progress bar; empty: no bar.
  std::string progress_label;
  /// Threads to step with (--threads); 0: the faster of one and all, by the clock
  /// (ThreadChooser).
  int threads = 0;
};

/// Steps `sim` until `frames` frames are done, it diverges, or SIGINT/SIGTERM/SIGHUP arrives
/// (the frame under way stops at its next substep; the state is kept where it stopped).
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

/// The method for a summary: its name, and for auto what it chose and how it adapted
/// ("auto: xpbd single, 4 substeps, 4 line passes, 1 stiff sweep; raised 2, lowered 1").
std::string method_text(const Simulation& sim);

/// The exit code for a finished run: 0, 3 (diverged: reported with the frame, the reason and a
/// hint), 129/130/143 (interrupted: reported with the frame and what was kept, `kept`) or 5 (an
/// output failed during the run: reported with the frame).
int exit_code(const std::string& scene, const Simulation& sim, const RunResult& run,
              const char* kept);

}  // namespace drape::app

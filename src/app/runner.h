// Runs a simulation for a number of frames, timing each, watching for divergence and
// interrupts; shared by `drape run` and the commands that build on it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/simulation.h"

namespace drape::app {

enum class RunStatus { ok, diverged, interrupted };
const char* to_string(RunStatus s);

struct RunResult {
  RunStatus status = RunStatus::ok;
  int64_t frames = 0;             ///< frames simulated
  double wall_seconds = 0.0;      ///< whole loop, exports included
  double setup_ms = 0.0;          ///< building the simulation
  std::vector<double> frame_ms;   ///< wall time of each frame's step alone
  int signal = 0;                 ///< the signal that interrupted the run, or 0
  double median_ms() const;
};

struct RunHooks {
  /// Called after each frame (and once before the first, with frame() == 0). May throw.
  std::function<void(const Simulation&)> after_frame;
  /// Text after the progress bar; empty: no bar.
  std::string progress_label;
};

/// Steps `sim` until `frames` frames are done, it diverges, or SIGINT/SIGTERM arrives (the
/// frame under way is finished first).
RunResult run_frames(Simulation& sim, int64_t frames, const RunHooks& hooks);

/// The stats other tools read (keys documented in the README).
nlohmann::json stats_json(const Simulation& sim, const RunResult& run);

}  // namespace drape::app

// The stats of a run, as `drape run --stats` writes them and the Python module's stats()
// returns them: one implementation, so both give the same keys with the same meaning (listed in
// the README).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/simulation.h"

namespace drape::io {

/// How a run ended: all its frames, diverged, stopped by a signal, or stopped because an output
/// written during it (an exported frame, a picture) could not be written.
enum class RunStatus { ok, diverged, interrupted, output_failed };
const char* to_string(RunStatus s);

/// What the loop that stepped a simulation saw.
struct RunResult {
  RunStatus status = RunStatus::ok;
  int64_t frames = 0;            ///< frames simulated
  double wall_seconds = 0.0;     ///< the whole loop, exports included
  double setup_ms = 0.0;         ///< building the simulation
  std::vector<double> frame_ms;  ///< wall time of each frame's step alone
  int signal = 0;                ///< the signal that interrupted the run, or 0
  std::string output_error;      ///< why an output failed (status output_failed), else empty
  /// The median of frame_ms (0 for none).
  double median_ms() const;
};

/// The stats other tools read: the run's figures and the simulation's state at its end.
nlohmann::json stats_json(const Simulation& sim, const RunResult& run);

/// A figure for JSON, which has no infinities or NaN: the number when finite, else the string
/// "inf", "-inf" or "nan" (never null, so a reader sees what went wrong).
nlohmann::json figure(double x);

/// JSON text as drape writes it: indented, and any invalid UTF-8 in strings (a name set with
/// --set can hold any bytes) replaced rather than thrown on.
std::string json_text(const nlohmann::json& j);

}  // namespace drape::io

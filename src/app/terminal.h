// Terminal output for long runs: a progress bar on a terminal, nothing when piped; and the
// SIGINT/SIGTERM/SIGHUP flag that stops a run at its next substep, so that it writes what it
// has and exits cleanly.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

namespace drape::app {

class Progress {
 public:
  /// Draws on stderr only when it is a terminal and `enabled`.
  Progress(std::string label, int64_t total, bool enabled);
  ~Progress();
  /// `done` of `total` finished; `detail` follows the bar. Redraws at most ten times a second.
  void update(int64_t done, const std::string& detail);
  /// Clears the bar's line.
  void finish();

 private:
  std::string label_;
  int64_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

/// Installs handlers for SIGINT, SIGTERM and SIGHUP (unless ignored, as under nohup) that
/// record the first signal; a second one ends the process at once, as if unhandled.
void install_interrupt_handlers();
/// The signal received since install_interrupt_handlers(), or 0.
int interrupt_signal();
/// Turns true with the first signal: for Simulation::set_stop_flag, so that a long frame stops
/// at its next substep.
const std::atomic<bool>* interrupt_flag();
/// The conventional exit code for a run stopped by `signal`: 128 + signal (129, 130, 143).
inline int interrupt_exit_code(int signal) { return 128 + signal; }

}  // namespace drape::app

// Stepping a simulation until the cloth comes to rest: what both lab tests wait for before
// they measure.
#pragma once

#include <functional>

#include "drape/simulation.h"

namespace drape::lab {

struct Settled {
  int frames = 0;        ///< frames stepped
  bool at_rest = false;  ///< every particle slower than the speed asked for, several frames running
  bool failed = false;   ///< the simulation diverged or was stopped
};

/// Steps `sim` until no particle moves faster than `speed` (m/s) for 5 frames running, at least
/// `least` and at most `most` frames. `each_frame`, if given, is called with the frames done.
Settled settle(Simulation& sim, double speed, int least, int most,
               const std::function<void(int)>& each_frame = {});

/// Records in a lab result (its stopped, diverged, diverged_frame and message) why `sim` ended a
/// failed settle: interrupted, or blown up at a frame, with the simulation's message.
template <class Result>
void record_failure(const Simulation& sim, Result& out) {
  out.stopped = sim.stopped() || sim.stop_requested();
  out.diverged = sim.diverged();
  out.diverged_frame = sim.diverged_frame();
  out.message = sim.divergence();
}

}  // namespace drape::lab

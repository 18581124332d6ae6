#include "lab/settle.h"

namespace drape::lab {

Settled settle(Simulation& sim, double speed, int least, int most,
               const std::function<void(int)>& each_frame) {
  Settled out;
  int calm = 0;
  const double speed2 = speed * speed;
  while (out.frames < most) {
    if (!sim.step() || sim.stopped() || sim.stop_requested()) {
      out.failed = true;
      return out;
    }
    ++out.frames;
    if (each_frame) each_frame(out.frames);
    double fastest2 = 0.0;
    for (const Vec3& v : sim.state().v) fastest2 = std::max(fastest2, v.squaredNorm());
    calm = fastest2 < speed2 ? calm + 1 : 0;
    if (calm >= 5 && out.frames >= least) {
      out.at_rest = true;
      return out;
    }
  }
  return out;
}

}  // namespace drape::lab

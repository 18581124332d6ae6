// The elastica of a strip clamped level at one end and bent by its own weight: the closed
// problem Peirce's cantilever test rests on, solved numerically for the lab and the tests.
#pragma once

namespace drape::lab {

/// Where the free end of the strip lies, from the clamp: how far along and how far down (m).
struct StripTip {
  double along = 0.0;
  double drop = 0.0;
};

/// The strip of free length L (m), rigidity B (N·m, per width) and weight w (N/m², per area)
/// clamped level at s = 0: B·θ''(s) = −w·(L − s)·cos θ(s), θ(0) = 0, θ'(L) = 0, θ the angle
/// below the horizontal. Solved by shooting on θ'(0) (bisection, RK4 along s).
StripTip elastica_tip(double B, double w, double L);

/// The free length at which the tip lies on the plane through the clamp inclined `angle`
/// (radians, in (0, π/2)) below the horizontal: what the cantilever test measures.
double elastica_overhang(double B, double w, double angle);

}  // namespace drape::lab

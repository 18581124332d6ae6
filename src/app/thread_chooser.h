// The default thread count, chosen by the clock. Two threads halve a large frame on an idle
// machine, but where another program keeps a core busy every barrier of a parallel loop waits
// for the thread the system has set aside, and frames took 2-3 times as long as on one thread
// (README, Performance). No OpenMP setting fixes both (OMP_WAIT_POLICY=passive is slower than
// one thread even on an idle machine), so a run without --threads times a few frames on each
// count now and then and steps with the faster. The thread count never changes the bits
// (Determinism.TheThreadCountDoesNotChangeTheBits), so neither does the choice.
#pragma once

namespace drape::app {

class ThreadChooser {
 public:
  /// `threads` > 0 (given with --threads): always that many. 0: chooses between one thread and
  /// OpenMP's default count for the calling thread, frame by frame.
  explicit ThreadChooser(int threads);
  /// Sets the calling thread's count for the next frame.
  void before_frame();
  /// The wall time of the frame just stepped.
  void after_frame(double ms);
  int threads() const { return current_; }

 private:
  static constexpr int kTrial = 6;   ///< frames timed on each count
  static constexpr int kHold = 300;  ///< frames on the faster one before timing again (5 s)
  bool choosing_ = false;
  int many_ = 1, current_ = 1;
  int frame_ = 0;  ///< frames into the present cycle of trials and hold
  double many_ms_ = 0.0, one_ms_ = 0.0;
};

}  // namespace drape::app

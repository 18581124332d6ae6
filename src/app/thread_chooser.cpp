#include "app/thread_chooser.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace drape::app {

ThreadChooser::ThreadChooser(int threads) {
#ifdef _OPENMP
  many_ = threads > 0 ? threads : omp_get_max_threads();
#endif
  current_ = many_;
  choosing_ = threads <= 0 && many_ > 1;
}

void ThreadChooser::before_frame() {
  if (choosing_) {
    // A cycle: kTrial frames on many threads, kTrial on one, then kHold on the faster.
    if (frame_ < kTrial)
      current_ = many_;
    else if (frame_ < 2 * kTrial)
      current_ = 1;
    else if (frame_ == 2 * kTrial)
      current_ = one_ms_ < many_ms_ ? 1 : many_;
  }
#ifdef _OPENMP
  omp_set_num_threads(current_);
#endif
}

void ThreadChooser::after_frame(double ms) {
  if (!choosing_) return;
  // Totals, not medians: on a busy machine most frames on two threads are as quick as ever and
  // a few take many times as long, and those are the cost.
  if (frame_ < kTrial)
    many_ms_ += ms;
  else if (frame_ < 2 * kTrial)
    one_ms_ += ms;
  if (++frame_ == 2 * kTrial + kHold) frame_ = 0, many_ms_ = one_ms_ = 0.0;
}

}  // namespace drape::app

#pragma once
// When a run has stopped converging. Its convergence measure (the larger of the
// mean-flow drop and the turbulence model's drop, what convergence itself waits
// for) is compared with an anchor: the last value that beat the previous anchor by
// the factor `fall`. A run whose measure has not beaten its anchor for `window`
// iterations has stalled — a plateau, a limit cycle or a slow wander — and ends
// instead of iterating silently to its limit.
//
// The anchor, not a fit over a window, so that noise in a falling history (the
// k-epsilon plates fall in bursts) never stops a run that is still making
// progress, and one number states the rule. The default window is chosen in
// turbulence/DESIGN.md from the histories of every ladder run.
#include "core/types.hpp"

namespace narwhal {

class StallDetector {
 public:
  // window 0: never stalls.
  StallDetector(int window, Real fall) : window_(window), fall_(fall) {}

  // This iteration's measure; true when the run has stalled with it.
  bool observe(int iteration, Real measure);

  // The anchor and the iteration it was set (restarts carry both: a resumed run
  // judges as the uninterrupted one did). Anchor < 0: nothing observed yet.
  Real anchor() const { return anchor_; }
  int anchor_iteration() const { return anchor_iteration_; }
  void restore(Real anchor, int anchor_iteration) {
    anchor_ = anchor;
    anchor_iteration_ = anchor_iteration;
  }

  int window() const { return window_; }
  Real fall() const { return fall_; }

 private:
  int window_;
  Real fall_;
  Real anchor_ = -1.0;
  int anchor_iteration_ = 0;
};

}  // namespace narwhal

#pragma once
// Self-propulsion in a steady run (issue 19): the propulsor's rotation rate moved until its
// thrust balances the vehicle's resistance at the commanded (towing) speed. Every
// `interval` cycles, once the flow has answered the last change, n takes a damped Newton
// step on the surplus S = T(n) - R: dS/dn is taken as dT/dn from the open-water curve at
// the present advance speed, the resistance's rise with n (the thrust deduction) left to
// the following steps, which the damping keeps from overshooting.
#include <optional>

#include "core/types.hpp"

namespace narwhal {

struct RpmControlSettings {
  int interval = 10;         // cycles between steps of n
  Real relaxation = 0.7;     // of the Newton step
  Real tolerance = 2e-3;     // settled when |T - R| <= tolerance R
  Real max_change = 0.2;     // the largest relative change of n in one step
};

class RpmController {
 public:
  explicit RpmController(RpmControlSettings s);

  // At cycle `cycle`: the new rotation rate (n itself between steps). thrust_slope = dT/dn.
  Real update(int cycle, Real rps, Real thrust, Real resistance, Real thrust_slope);
  // Whether the last measured surplus lay within the tolerance.
  bool settled() const { return settled_; }
  Real surplus() const { return surplus_; }  // (T - R) / R when last measured
  int steps() const { return steps_; }

  // What a restart carries to continue exactly.
  struct State {
    int last_step_cycle = 0;
    int steps = 0;
    Real surplus = 0.0;
    bool settled = false;
  };
  State state() const { return {last_step_cycle_, steps_, surplus_, settled_}; }
  void restore(const State& s);

 private:
  RpmControlSettings s_;
  int last_step_cycle_ = 0, steps_ = 0;
  Real surplus_ = 0.0;
  bool settled_ = false;
};

}  // namespace narwhal

#pragma once
// The CFL controller's state, as NewtonSolver keeps it and restarts carry it whole.
#include "core/types.hpp"
#include "implicit/cfl_rise_guard.hpp"

namespace narwhal {

// What the CFL controller carries from one iteration to the next (§6.6 SER and what limits
// it): SER's reference norm (< 0: not yet fixed), the last CFL (which cfl_growth limits
// from; < 0: none yet), whether the CFL is regrowing after a rejected correction cut it,
// and the rise guard's ceiling and watch (implicit/cfl_rise_guard.hpp).
struct CflControlState {
  Real reference_norm = -1.0;
  Real last_cfl = -1.0;
  bool recovering = false;
  CflRiseGuard::State rise_guard{};
};

}  // namespace narwhal

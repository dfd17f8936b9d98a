#include "propulsion/rpm_controller.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace narwhal {

RpmController::RpmController(RpmControlSettings s) : s_(s) {
  if (s_.interval < 1) fail("rpm controller: the interval must be at least one cycle, got {}", s_.interval);
  if (!(s_.relaxation > 0.0 && s_.relaxation <= 1.0))
    fail("rpm controller: the relaxation must lie in (0, 1], got {}", s_.relaxation);
  if (!(s_.tolerance > 0.0)) fail("rpm controller: the tolerance must be positive, got {}", s_.tolerance);
  if (!(s_.max_change > 0.0)) fail("rpm controller: the largest change must be positive, got {}", s_.max_change);
}

Real RpmController::update(int cycle, Real rps, Real thrust, Real resistance, Real thrust_slope) {
  if (!(resistance > 0.0)) {  // the flow has not yet built a resistance to balance
    settled_ = false;
    return rps;
  }
  surplus_ = (thrust - resistance) / resistance;
  settled_ = std::abs(surplus_) <= s_.tolerance;
  if (cycle - last_step_cycle_ < s_.interval || settled_) return rps;
  if (!(thrust_slope > 0.0))
    fail("rpm controller: the thrust does not rise with the rotation rate (dT/dn = {:.3e} at n = {:.4g}); the "
         "open-water curve's K_T falls too steeply at this advance ratio",
         thrust_slope, rps);
  const Real step = -s_.relaxation * (thrust - resistance) / thrust_slope;
  const Real limit = s_.max_change * rps;
  last_step_cycle_ = cycle;
  ++steps_;
  return rps + std::clamp(step, -limit, limit);
}

void RpmController::restore(const State& s) {
  last_step_cycle_ = s.last_step_cycle;
  steps_ = s.steps;
  surplus_ = s.surplus;
  settled_ = s.settled;
}

}  // namespace narwhal

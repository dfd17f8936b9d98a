#pragma once
// Ballast changed in time: tanks blown (or flooded) while a free body moves (issue 19's
// ballast-blow manoeuvre). A change of weight dW at a tank, as a step at `start` or a
// linear ramp over `duration`, enters §11.3's hydrostatic loads as the weight the body
// loses, -dW s(t) g_B, at the tank (body axes, about O); RK4 evaluates it exactly at each
// stage's time and attitude (§11.6), as it does the weight and buoyancy.
//
// The body's mass and inertia stay those of the case: the water a blow moves is a small
// part of a submarine's displacement (the ballast blow's 0.5 % to 2 %), and §11.2's mass
// matrix is kept constant (factorised once).
#include <vector>

#include "core/types.hpp"
#include "motion/rigid_body.hpp"

namespace narwhal {

struct BallastChange {
  Real weight = 0.0;            // dW: the weight the body loses (> 0: blown; < 0: flooded)
  Vec3 tank = Vec3::Zero();     // the tank's centre relative to O, body axes
  Real start = 0.0;             // when the change begins
  Real duration = 0.0;          // 0: a step at `start`; otherwise a linear ramp over it

  // The part of dW lost by time t: 0 before `start`, 1 once the ramp is over.
  Real fraction(Real t) const;
};

// The loads of the weight lost by time t, body axes about O; `down_body` is gravity's
// direction in body axes (unit).
BodyLoads ballast_loads(const std::vector<BallastChange>& changes, const Vec3& down_body, Real t);

}  // namespace narwhal

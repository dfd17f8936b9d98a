#pragma once
// Trimmed at release: a manoeuvre starts from straight and level flight, so the loads the
// body feels at t = 0 (the flow's, the propulsor's, weight and buoyancy; not the ballast
// changes the manoeuvre makes) are balanced, as a crew trims a submarine: in heave by a
// weight added at O (water taken into a trim tank there, dW > 0, or pumped out), in pitch
// by water moved between trim tanks fore and aft (a couple: its weight's first moment
// along x_B, s = sum dW_i x_i). Both then act as weights, turning with gravity in body
// axes. The mass matrix stays the case's (as for ballast: motion/ballast.hpp).
#include "motion/rigid_body.hpp"

namespace narwhal {

struct TrimSpec {
  bool heave = false;
  bool pitch = false;
  bool any() const { return heave || pitch; }
};

struct TrimWeights {
  Real weight = 0.0;        // dW added at O
  Real first_moment = 0.0;  // s, along x_B
  // Their loads with gravity along `down_body` (unit, body axes), about O.
  BodyLoads loads(const Vec3& down_body) const;
};

// The weights that balance, in the degrees of freedom `spec` names, the loads on a body
// of equations `body` in state `at_release`: `loads` (body axes, about O: the flow's or a
// model's) and the hydrostatics. Throws Error when gravity is more than 60 degrees off z_B.
TrimWeights trim_at_release(const TrimSpec& spec, const RigidBodyEquations& body, const RigidBodyState& at_release,
                            const BodyLoads& loads);

}  // namespace narwhal

#pragma once
// Classical RK4 for the 13 rigid-body ODEs, coupled to a flow solution that is known
// only at flow time levels (NUMERICS §11.6).
//
//  * Flow loads (hydrodynamic forces from §11.5, body axes) are interpolated in time:
//    stage 1 uses F^n, stages 2 and 3 use (F^n + F^{n+1,*})/2, stage 4 uses F^{n+1,*},
//    where F^{n+1,*} is the caller's estimate (2F^n - F^{n-1} for loose coupling, the
//    latest Newton iterate for strong coupling).
//  * Loads that depend on the state (hydrostatics, the propulsor's V_A) are evaluated
//    exactly at every stage: hydrostatics inside RigidBodyEquations::derivative, the
//    rest through `state_loads`.
// The linear interpolation makes the step second-order accurate in the flow loads (the
// order of the flow's own time discretization) and fourth-order in everything else.
// After the step the quaternion is renormalised; the size of that correction is
// returned as a health check (§11.4: below 1e-10 per step for a sensible step).
#include <array>
#include <functional>

#include "motion/rigid_body.hpp"

namespace narwhal {

using StateDependentLoads = std::function<BodyLoads(const RigidBodyState&, Real time)>;

struct RigidBodyStep {
  RigidBodyState state;
  Real quaternion_norm_error = 0.0;  // | |e| - 1 | before renormalising
};

RigidBodyStep advance_rk4(const RigidBodyEquations& body, const RigidBodyState& s, Real time, Real step,
                          const BodyLoads& flow_loads_now, const BodyLoads& flow_loads_next,
                          const StateDependentLoads& state_loads = nullptr);

// The same step with each stage's flow loads given (stage 1 at t^n, stages 2 and 3 at
// t^n + h/2, stage 4 at t^{n+1}); `stage_accelerations`, when given, receives each
// stage's (dv/dt, dw/dt). The coupling adds its added-mass term per stage (§11.7).
RigidBodyStep advance_rk4_stages(const RigidBodyEquations& body, const RigidBodyState& s, Real time, Real step,
                                 const std::array<BodyLoads, 4>& flow_loads, const StateDependentLoads& state_loads,
                                 std::array<Vec6, 4>* stage_accelerations = nullptr);

}  // namespace narwhal

#include "motion/rk4.hpp"

#include <cmath>

namespace narwhal {

RigidBodyStep advance_rk4(const RigidBodyEquations& body, const RigidBodyState& s, Real t, Real h,
                          const BodyLoads& flow_now, const BodyLoads& flow_next, const StateDependentLoads& state_loads) {
  const BodyLoads flow_mid = 0.5 * (flow_now + flow_next);
  return advance_rk4_stages(body, s, t, h, {flow_now, flow_mid, flow_mid, flow_next}, state_loads);
}

RigidBodyStep advance_rk4_stages(const RigidBodyEquations& body, const RigidBodyState& s, Real t, Real h,
                                 const std::array<BodyLoads, 4>& flow, const StateDependentLoads& state_loads,
                                 std::array<Vec6, 4>* stage_accelerations) {
  auto f = [&](const RigidBodyVector& y, Real time, int stage) {
    RigidBodyState at;
    at.y = y;
    BodyLoads loads = flow[stage];
    if (state_loads) loads += state_loads(at, time);
    const RigidBodyVector d = body.derivative(at, loads).y;
    if (stage_accelerations) (*stage_accelerations)[stage] = d.head<6>();
    return d;
  };
  const RigidBodyVector k1 = f(s.y, t, 0);
  const RigidBodyVector k2 = f(s.y + 0.5 * h * k1, t + 0.5 * h, 1);
  const RigidBodyVector k3 = f(s.y + 0.5 * h * k2, t + 0.5 * h, 2);
  const RigidBodyVector k4 = f(s.y + h * k3, t + h, 3);
  RigidBodyStep out;
  out.state.y = s.y + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  const Real norm = out.state.attitude().norm();
  out.quaternion_norm_error = std::abs(norm - 1.0);
  out.state.attitude() /= norm;
  return out;
}

}  // namespace narwhal

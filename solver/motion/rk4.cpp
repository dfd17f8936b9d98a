#include "motion/rk4.hpp"

#include <cmath>

namespace narwhal {

RigidBodyStep advance_rk4(const RigidBodyEquations& body, const RigidBodyState& s, Real t, Real h,
                          const BodyLoads& flow_now, const BodyLoads& flow_next, const StateDependentLoads& state_loads) {
  const BodyLoads flow_mid = 0.5 * (flow_now + flow_next);
  auto f = [&](const RigidBodyVector& y, Real time, const BodyLoads& flow) {
    RigidBodyState stage;
    stage.y = y;
    BodyLoads loads = flow;
    if (state_loads) loads += state_loads(stage, time);
    return body.derivative(stage, loads).y;
  };
  const RigidBodyVector k1 = f(s.y, t, flow_now);
  const RigidBodyVector k2 = f(s.y + 0.5 * h * k1, t + 0.5 * h, flow_mid);
  const RigidBodyVector k3 = f(s.y + 0.5 * h * k2, t + 0.5 * h, flow_mid);
  const RigidBodyVector k4 = f(s.y + h * k3, t + h, flow_next);
  RigidBodyStep out;
  out.state.y = s.y + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  const Real norm = out.state.attitude().norm();
  out.quaternion_norm_error = std::abs(norm - 1.0);
  out.state.attitude() /= norm;
  return out;
}

}  // namespace narwhal

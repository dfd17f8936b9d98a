// A free body trimmed at release (motion/coupled_body.hpp, TrimSpec): the loads at t = 0,
// the flow's and the hydrostatics', are balanced by a weight at O (heave) and a first
// moment of weight along x_B (pitch), so that a body whose flow loads stay those of
// release stays at rest; the weights turn with gravity, and a restart carries them.
#include <gtest/gtest.h>

#include <cmath>

#include "motion/coupled_body.hpp"

namespace narwhal {
namespace {

// Mass 2, slightly heavy (W 2.1, B 2), its centre of gravity 0.05 ahead of O: free in
// surge, heave and pitch, gravity along `down` (earth axes).
CoupledBody body(TrimSpec trim, const Vec3& down = Vec3::UnitZ()) {
  MassProperties mp;
  mp.mass = 2.0;
  mp.inertia_o = Vec3(0.2, 0.5, 0.5).asDiagonal();
  mp.weight = 2.1;
  mp.buoyancy = 2.0;
  mp.r_g = Vec3(0.05, 0.0, 0.0);
  mp.down = down.normalized();
  AccelerationOptions o;
  o.free = {false, false, true, false, true, false};
  return CoupledBody(mp, o, body_state_at_release(Vec3::Zero(), Vec3::Zero(), Vec3::Zero()),
                     CouplingSettings{1.0, 1e-14}, {}, trim);
}

// The flow's loads, constant: Z 0.03 (body axes) and M -0.02, given in earth axes (the
// body's at release: x_B = -x, y_B = -y, z_B = z).
BodyLoads flow_earth() { return {Vec3(0.0, 0.0, 0.03), Vec3(0.0, 0.02, 0.0)}; }

std::vector<RigidBodyState> fly(CoupledBody& b, Real dt, int steps, int first_step = 0) {
  std::vector<RigidBodyState> out;
  for (int n = first_step; n < first_step + steps; ++n) {
    b.begin_step(n * dt, dt, n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
    for (int m = 0; m < 20 && !b.converged(b.correct(flow_earth())); ++m) {
    }
    out.push_back(b.state());
  }
  return out;
}

TEST(Trim, TheWeightsBalanceTheLoadsAtRelease) {
  // Z: 0.03 + (W - B) + dW = 0; M: -0.02 - W x_G + s = 0 (a weight ahead of O pitches
  // the nose down: M = -W x_G with z_B down).
  CoupledBody b = body({true, true});
  b.observe_initial_loads(flow_earth());
  EXPECT_NEAR(b.trim().weight, -0.03 - 0.1, 1e-15);
  EXPECT_NEAR(b.trim().first_moment, -0.02 - 2.1 * 0.05, 1e-15);
}

TEST(Trim, ATrimmedBodyUnderItsReleaseLoadsStaysAtRest) {
  CoupledBody trimmed = body({true, true});
  trimmed.observe_initial_loads(flow_earth());
  for (const RigidBodyState& s : fly(trimmed, 0.02, 50)) {
    EXPECT_LT(s.velocity().norm(), 1e-14);
    EXPECT_LT(s.angular_velocity().norm(), 1e-14);
  }
  // Untrimmed, or trimmed in one degree of freedom only, the same body moves in the other.
  CoupledBody untrimmed = body({});
  untrimmed.observe_initial_loads(flow_earth());
  const RigidBodyState u = fly(untrimmed, 0.02, 50).back();
  EXPECT_GT(std::abs(u.velocity()[2]), 1e-3);
  EXPECT_GT(std::abs(u.angular_velocity()[1]), 1e-3);
  CoupledBody heave_only = body({true, false});
  heave_only.observe_initial_loads(flow_earth());
  EXPECT_GT(std::abs(fly(heave_only, 0.02, 50).back().angular_velocity()[1]), 1e-3);
}

TEST(Trim, TheWeightsTurnWithGravity) {
  // Gravity 20 degrees off z_B in the x-z plane (earth +x is body -x): the weight dW
  // at O pulls along gravity, so it also pushes along x_B, and the heave balance divides
  // by gravity's z_B component.
  const Real a = 20.0 * std::acos(-1.0) / 180.0;
  CoupledBody b = body({true, true}, Vec3(std::sin(a), 0.0, std::cos(a)));
  b.observe_initial_loads(flow_earth());
  const Vec3 d(-std::sin(a), 0.0, std::cos(a));  // body axes
  const BodyLoads l = b.trim().loads(d);
  EXPECT_NEAR(l.force.x(), b.trim().weight * d.x(), 1e-15);
  EXPECT_NEAR(l.force.z(), b.trim().weight * d.z(), 1e-15);
  EXPECT_NEAR(l.moment.y(), -b.trim().first_moment * d.z(), 1e-15);
  // Z and M balanced at release all the same.
  const BodyLoads total = BodyLoads{Vec3(0.0, 0.0, 0.03), Vec3(0.0, -0.02, 0.0)} +
                          b.equations().hydrostatic_loads(b.state()) + l;
  EXPECT_NEAR(total.force.z(), 0.0, 1e-15);
  EXPECT_NEAR(total.moment.y(), 0.0, 1e-15);
}

TEST(Trim, ARestartCarriesTheTrimAndIsNotTrimmedAgain) {
  CoupledBody whole = body({true, true});
  whole.observe_initial_loads(flow_earth());
  fly(whole, 0.02, 5);
  CoupledBody restarted = body({true, true});
  // A restarted run observes the loads of its restart's flow before the body's state is
  // restored: the checkpoint's trim stands.
  restarted.observe_initial_loads(BodyLoads{Vec3(0.0, 0.0, 0.5), Vec3::Zero()});
  restarted.restore(whole.checkpoint());
  EXPECT_EQ(restarted.trim().weight, whole.trim().weight);
  EXPECT_EQ(restarted.trim().first_moment, whole.trim().first_moment);
  EXPECT_EQ(fly(restarted, 0.02, 5, 5).back().y, fly(whole, 0.02, 5, 5).back().y);
}

}  // namespace
}  // namespace narwhal

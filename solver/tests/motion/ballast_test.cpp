// Ballast changed in time (motion/ballast.hpp): the weight a tank loses acts against
// gravity at the tank, as a step or a ramp, evaluated at RK4's stage times, so that a
// body held to heave integrates it exactly when the ramp's ends fall on steps.
#include <gtest/gtest.h>

#include <cmath>

#include "motion/ballast.hpp"
#include "motion/coupled_body.hpp"

namespace narwhal {
namespace {

// A neutral body of mass 2 (I_y 0.5), free in `dof` alone, gravity along the grid's +z:
// with body_state_at_release's axes (z_B = z) z_B points down, as marine axes do.
CoupledBody neutral_body(int dof, std::vector<BallastChange> ballast) {
  MassProperties mp;
  mp.mass = 2.0;
  mp.inertia_o = Vec3(0.2, 0.5, 0.5).asDiagonal();
  mp.weight = mp.buoyancy = 2.0;
  mp.down = Vec3::UnitZ();
  AccelerationOptions o;
  o.free.fill(false);
  o.free[static_cast<std::size_t>(dof)] = true;
  return CoupledBody(mp, o, body_state_at_release(Vec3::Zero(), Vec3::Zero(), Vec3::Zero()),
                     CouplingSettings{1.0, 1e-14}, std::move(ballast));
}

// Steps of dt in still air (no flow loads), each coupled to convergence; the body's
// state after each.
std::vector<RigidBodyState> fly(CoupledBody& b, Real dt, int steps) {
  std::vector<RigidBodyState> out;
  for (int n = 0; n < steps; ++n) {
    b.begin_step(n * dt, dt, n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
    for (int m = 0; m < 20 && !b.converged(b.correct(BodyLoads{})); ++m) {
    }
    out.push_back(b.state());
  }
  return out;
}

TEST(Ballast, FractionIsAStepOrARamp) {
  const BallastChange step{1.0, Vec3::Zero(), 0.5, 0.0}, ramp{1.0, Vec3::Zero(), 0.5, 0.2};
  EXPECT_EQ(step.fraction(0.49), 0.0);
  EXPECT_EQ(step.fraction(0.5), 1.0);
  EXPECT_EQ(ramp.fraction(0.5), 0.0);
  EXPECT_DOUBLE_EQ(ramp.fraction(0.55), 0.25);
  EXPECT_EQ(ramp.fraction(0.9), 1.0);
}

TEST(Ballast, TheWeightLostLiftsTheBodyAtTheTank) {
  // Gravity along body z (down_B = +z_B): a blown tank pushes along -z_B, and at a tank
  // ahead of O (x_B > 0) it pitches the nose up (M > 0 about y_B).
  const std::vector<BallastChange> tanks{{0.3, Vec3(0.4, 0.0, 0.1), 0.0, 0.0}, {-0.1, Vec3(-0.2, 0.0, 0.0), 0.0, 0.0}};
  const BodyLoads l = ballast_loads(tanks, Vec3::UnitZ(), 1.0);
  EXPECT_TRUE(l.force.isApprox(Vec3(0.0, 0.0, -0.2), 1e-15));
  EXPECT_TRUE(l.moment.isApprox(Vec3(0.0, 0.4 * 0.3 + 0.2 * 0.1, 0.0), 1e-15));
}

TEST(Ballast, HeldToHeaveTheBodyRisesWithTheIntegralOfTheRamp) {
  // dW 0.2 over a ramp from t = 0.05 to 0.15: w' = -(dW / m) s(t), up being -z_B. RK4's
  // stages see the ramp exactly; its ends fall on steps.
  CoupledBody b = neutral_body(2, {{0.2, Vec3(0.3, 0.0, 0.0), 0.05, 0.1}});
  const Real dt = 0.01;
  const std::vector<RigidBodyState> s = fly(b, dt, 30);
  const auto exact_w = [](Real t) {
    const Real a = 0.2 / 2.0;  // dW / m
    if (t <= 0.05) return 0.0;
    if (t <= 0.15) return a * (t - 0.05) * (t - 0.05) / (2.0 * 0.1);
    return a * (0.05 + (t - 0.15));
  };
  for (int n = 0; n < 30; ++n) {
    const Real t = (n + 1) * dt;
    EXPECT_NEAR(s[static_cast<std::size_t>(n)].velocity()[2], -exact_w(t), 1e-15) << "t = " << t;
    EXPECT_EQ(s[static_cast<std::size_t>(n)].angular_velocity().norm(), 0.0);
  }
}

TEST(Ballast, HeldToPitchATankAheadOfTheOriginTurnsTheNoseUp) {
  // A step of dW 0.2 at x_B = 0.3: q' = M / I_y = 0.3 * 0.2 / 0.5 at first (the moment
  // falls as cos(theta) when the body turns: 2 % by t = 0.1).
  CoupledBody b = neutral_body(4, {{0.2, Vec3(0.3, 0.0, 0.0), 0.0, 0.0}});
  const std::vector<RigidBodyState> s = fly(b, 0.01, 10);
  const Real q = s.back().angular_velocity()[1], first = 0.3 * 0.2 / 0.5 * 0.1;
  EXPECT_GT(q, 0.0);
  EXPECT_NEAR(q, first, 0.02 * first);
  EXPECT_GT(b.turn_since_release(s.back()).pitch, 0.0);
}

}  // namespace
}  // namespace narwhal

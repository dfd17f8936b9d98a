// Strong coupling of the rigid body with a flow (NUMERICS §11.6-11.7), against a model
// fluid whose force answers the body's estimated motion at once, as an incompressible
// flow does: F = -m_a (V^{n+1} - V^n) / dt - c V^{n+1} (earth axes). The coupled
// iteration must converge to the body's motion with its added mass, and its stability
// limit must be the one coupled_body.hpp states.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "motion/coupled_body.hpp"

namespace narwhal {
namespace {

struct ModelFluid {
  Real added_mass = 0.5, damping = 1.0;
  BodyLoads force_on(const CoupledBody& b, Real dt) const {
    const Mat3 r1 = rotation_matrix(b.state().attitude()), r0 = rotation_matrix(b.start_of_step().attitude());
    const Vec3 v1 = r1 * Vec3(b.state().velocity()), v0 = r0 * Vec3(b.start_of_step().velocity());
    return {-added_mass * (v1 - v0) / dt - damping * v1, Vec3::Zero()};
  }
};

// A sphere of mass 1 with net weight 1 along the grid's -z.
MassProperties falling_sphere() {
  MassProperties mp;
  mp.mass = 1.0;
  mp.inertia_o = 0.1 * Mat3::Identity();
  mp.weight = 3.0;
  mp.buoyancy = 2.0;
  mp.down = -Vec3::UnitZ();
  return mp;
}

CoupledBody released(Real relaxation, const Mat6& estimate = Mat6::Zero()) {
  AccelerationOptions o;
  o.added_mass_estimate = estimate;
  return CoupledBody(falling_sphere(), o, body_state_at_release(Vec3(1.0, 2.0, 3.0), Vec3::Zero(), Vec3::Zero()),
                     CouplingSettings{relaxation, 1e-12});
}

// The changes each correction makes in step `step` (1: the first after release), the
// steps before it coupled to convergence.
std::vector<Real> changes_in_step(CoupledBody& b, const ModelFluid& fluid, Real dt, int iterations, int step = 1) {
  for (int n = 1; n < step; ++n) {
    b.begin_step((n - 1) * dt, dt, n == 1 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
    for (int m = 0; m < 200; ++m) b.correct(fluid.force_on(b, dt));
  }
  b.begin_step((step - 1) * dt, dt, step == 1 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
  std::vector<Real> c;
  for (int m = 0; m < iterations; ++m) c.push_back(b.correct(fluid.force_on(b, dt)));
  return c;
}

TEST(CoupledBody, ReleasedAtRestTheGridStaysWhereItWasBuilt) {
  CoupledBody b = released(1.0);
  const RigidMotionSample s = b.sample(b.state());
  EXPECT_LT((s.pose.rotation - Mat3::Identity()).norm(), 1e-15);
  EXPECT_LT(s.pose.displacement.norm(), 1e-15);
  EXPECT_LT((b.pivot() - Vec3(1.0, 2.0, 3.0)).norm(), 1e-15);
  // Body axes are grid_axes.hpp's: a body velocity along x_B is along -x of the grid.
  RigidBodyState moving = b.state();
  moving.velocity() = Vec3(1.0, 0.0, 0.0);
  EXPECT_LT((b.sample(moving).velocity - Vec3(-1.0, 0.0, 0.0)).norm(), 1e-15);
}

TEST(CoupledBody, ConvergedCouplingFallsWithTheAddedMassAndReachesTerminalVelocity) {
  // Exact: V(t) = V_T (1 - exp(-t / tau)), V_T = (W - B) / c, tau = (m + m_a) / c. The
  // model's force is first order in dt: at dt = tau / 400 it is within 2e-3.
  const ModelFluid fluid{0.5, 1.0};
  CoupledBody b = released(1.0);
  const Real tau = 1.5, dt = tau / 400.0;
  Real t = 0.0;
  for (int n = 0; n < 1200; ++n) {
    b.begin_step(t, dt, n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
    for (int m = 0; m < 50 && !b.converged(b.correct(fluid.force_on(b, dt))); ++m) {
    }
    t += dt;
    if (n == 399 || n == 1199) {
      const Real exact = -(1.0 - std::exp(-t / tau));  // along -z
      const Vec3 v = b.sample(b.state()).velocity;
      EXPECT_NEAR(v[2], exact, 2e-3 * std::abs(exact)) << "t = " << t;
      EXPECT_NEAR(v[0], 0.0, 1e-14);
      EXPECT_NEAR(Vec3(b.state().position())[2] - 3.0 - (-(t - tau * (1.0 - std::exp(-t / tau)))), 0.0,
                  2e-3 * t);
    }
  }
}

TEST(CoupledBody, WithoutAnEstimateTheIterationContractsByTheAddedMassRatio) {
  // coupled_body.hpp: error factor 1 - omega (1 + m_a / m) in the first step after
  // release, 1 - omega (1 + m_a / (2 m)) in the steps after it (the model's damping adds
  // c dt / m = 0.01).
  for (const Real ratio : {0.5, 0.9}) {
    CoupledBody first = released(1.0), second = released(1.0);
    const auto c1 = changes_in_step(first, ModelFluid{ratio, 1.0}, 0.01, 6, 1);
    EXPECT_NEAR(c1[4] / c1[3], ratio + 0.01, 0.02 * ratio) << "m_a/m = " << ratio;
    const auto c2 = changes_in_step(second, ModelFluid{ratio, 1.0}, 0.01, 6, 2);
    EXPECT_NEAR(c2[4] / c2[3], ratio / 2.0, 0.02 * ratio) << "m_a/m = " << ratio;
  }
  for (const Real omega : {0.5, 0.6}) {
    CoupledBody b = released(omega);
    const auto c = changes_in_step(b, ModelFluid{1.5, 1.0}, 0.01, 6);
    EXPECT_NEAR(c[4] / c[3], std::abs(1.0 - omega * 2.51), 0.02) << "omega " << omega;
  }
}

TEST(CoupledBody, AboveTheLimitItDivergesUnlessRelaxedOrPreconditioned) {
  const ModelFluid light{2.4, 1.0};  // m_a / m = 2.4: factor -2.4 at omega = 1 in the first step
  CoupledBody plain = released(1.0);
  const auto grows = changes_in_step(plain, light, 0.01, 12);
  EXPECT_GT(grows.back(), 5.0 * grows[1]);
  CoupledBody relaxed = released(0.3);  // factor 1 - 0.3 * 3.41 = -0.02
  const auto shrinks = changes_in_step(relaxed, light, 0.01, 12);
  EXPECT_LT(shrinks.back(), 1e-8 * shrinks[1]);
  // A body ten times lighter than the fluid it moves, with an estimate 20 % low, in the
  // first step and in a later one.
  Mat6 estimate = Mat6::Zero();
  estimate.topLeftCorner<3, 3>() = 0.8 * 10.0 * Mat3::Identity();
  for (const int step : {1, 3}) {
    CoupledBody preconditioned = released(1.0, estimate);
    const auto fast = changes_in_step(preconditioned, ModelFluid{10.0, 1.0}, 0.01, 12, step);
    EXPECT_LT(fast.back(), 1e-4 * fast[1]) << "step " << step;
  }
}

TEST(CoupledBody, WithTheAddedMassAsEstimateTheIterationContractsForAnyMassRatio) {
  // coupled_body.hpp: with M_A = m_a the first step is solved at once and later steps
  // contract by m_a / (2 (m + m_a)) < 1/2.
  for (const Real ratio : {0.5, 2.0, 10.0, 100.0}) {
    Mat6 estimate = Mat6::Zero();
    estimate.topLeftCorner<3, 3>() = ratio * Mat3::Identity();
    CoupledBody first = released(1.0, estimate), later = released(1.0, estimate);
    const auto c1 = changes_in_step(first, ModelFluid{ratio, 1.0}, 0.01, 4, 1);
    EXPECT_LT(c1[2], 0.02 * c1[1]) << "m_a/m = " << ratio;
    const auto c = changes_in_step(later, ModelFluid{ratio, 1.0}, 0.01, 6, 3);
    EXPECT_NEAR(c[4] / c[3], ratio / (2.0 * (1.0 + ratio)), 0.02) << "m_a/m = " << ratio;
  }
}

TEST(CoupledBody, TheEstimateDoesNotChangeTheConvergedMotion) {
  Mat6 estimate = Mat6::Zero();
  estimate.topLeftCorner<3, 3>() = 0.4 * Mat3::Identity();
  CoupledBody plain = released(1.0), preconditioned = released(1.0, estimate);
  const ModelFluid fluid{0.5, 1.0};
  Real t = 0.0;
  for (int n = 0; n < 20; ++n, t += 0.05)
    for (CoupledBody* b : {&plain, &preconditioned}) {
      b->begin_step(t, 0.05, n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
      for (int m = 0; m < 100; ++m) b->correct(fluid.force_on(*b, 0.05));
    }
  EXPECT_LT((plain.state().y - preconditioned.state().y).norm(), 1e-13);
}

TEST(CoupledBody, TheGridsFaceSpeedsAreTheBodysVelocities) {
  // coupled_body.hpp: the BDF derivative of the origin's positions (the speed the swept
  // volumes give the grid's faces) is the body's velocity at t^{n+1}, step by step.
  const ModelFluid fluid{0.5, 1.0};
  MassProperties mp = falling_sphere();
  mp.down = Vec3(0.6, 0.0, -0.8);
  CoupledBody b(mp, {}, body_state_at_release(Vec3::Zero(), Vec3(0.2, 0.0, 0.0), Vec3(0.0, 0.3, 0.1)), {});
  std::vector<Vec3> x{Vec3(b.state().position())};
  const Real dt = 0.05;
  for (int n = 0; n < 8; ++n) {
    const BdfCoefficients c = n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0);
    b.begin_step(n * dt, dt, c);
    for (int m = 0; m < 30; ++m) b.correct(fluid.force_on(b, dt));
    x.push_back(Vec3(b.state().position()));
    const Vec3 rate = (c.c0 * x[n + 1] + c.c1 * x[n] + (n > 0 ? Vec3(c.c2 * x[n - 1]) : Vec3::Zero())) / dt;
    EXPECT_LT((rate - b.sample(b.state()).velocity).norm(), 1e-12) << "step " << n + 1;  // round-off over dt
  }
}

TEST(CoupledBody, HeldDegreesOfFreedomKeepTheirVelocity) {
  AccelerationOptions o;
  o.free = {true, true, false, true, false, true};  // heave and pitch held
  MassProperties mp = falling_sphere();
  mp.r_g = Vec3(0.1, 0.0, 0.05);  // couples surge and pitch through M_RB
  mp.down = Vec3(0.6, 0.0, 0.8);
  mp.inertia_o += mp.mass * (mp.r_g.squaredNorm() * Mat3::Identity() - mp.r_g * mp.r_g.transpose());
  CoupledBody b(mp, o, body_state_at_release(Vec3::Zero(), Vec3(0.0, 0.0, 0.3), Vec3::Zero()), {});
  for (int n = 0; n < 10; ++n) {
    b.begin_step(0.01 * n, 0.01, BdfCoefficients::bdf1());
    b.correct(BodyLoads{});
  }
  EXPECT_EQ(b.state().velocity()[2], 0.3);         // z_B = z: heave kept
  EXPECT_EQ(b.state().angular_velocity()[1], 0.0);  // pitch rate kept
  EXPECT_GT(std::abs(b.state().velocity()[0]), 1e-3);  // surge free: the weight's x part
}

TEST(CoupledBody, ARestoredBodyContinuesBitForBit) {
  const ModelFluid fluid{0.5, 1.0};
  auto run = [&](CoupledBody& b, int from, int to) {
    for (int n = from; n < to; ++n) {
      b.begin_step(0.05 * n, 0.05, n == 0 ? BdfCoefficients::bdf1() : BdfCoefficients::bdf2(1.0));
      for (int m = 0; m < 4; ++m) b.correct(fluid.force_on(b, 0.05));
    }
  };
  Mat6 estimate = Mat6::Zero();
  estimate.topLeftCorner<3, 3>() = 0.3 * Mat3::Identity();
  CoupledBody whole = released(0.7, estimate), first = released(0.7, estimate), second = released(0.7, estimate);
  run(whole, 0, 10);
  run(first, 0, 6);
  second.restore(first.checkpoint());
  run(second, 6, 10);
  EXPECT_EQ(whole.state().y, second.state().y);
  EXPECT_THROW(second.restore(std::vector<Real>(5, 0.0)), Error);
}

}  // namespace
}  // namespace narwhal

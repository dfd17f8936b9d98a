// Six-degree-of-freedom rigid body (NUMERICS §11): attitude algebra, hydrostatics in
// both of §11.3's forms, invariants of the torque-free body, independence of the
// choice of body origin, the hydrostatic roll period, exact free fall, and the orders
// of accuracy of RK4 with interpolated (2nd) and state-evaluated (4th) loads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "motion/rk4.hpp"

namespace narwhal {
namespace {

constexpr Real kPi = std::numbers::pi;

// A body with unequal principal moments whose principal axes are not the body axes
// (all products of inertia non-zero), with the CG away from the origin.
MassProperties tumbling_body(const Vec3& r_g) {
  MassProperties mp;
  mp.mass = 2.0;
  mp.r_g = r_g;
  const Mat3 q = (Eigen::AngleAxis<Real>(0.4, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const Mat3 inertia_g = q * Vec3(1.0, 2.0, 3.5).asDiagonal() * q.transpose();
  // parallel-axis theorem: I_O = I_G + m (|r|^2 1 - r r^T)
  mp.inertia_o = inertia_g + mp.mass * (r_g.squaredNorm() * Mat3::Identity() - r_g * r_g.transpose());
  return mp;
}

Vec3 earth_linear_momentum(const RigidBodyEquations& b, const RigidBodyState& s) {
  return rotation_matrix(s.attitude()) * b.linear_momentum_body(s);
}

// Angular momentum about the earth origin: x_O x p_E + R h_O.
Vec3 earth_angular_momentum(const RigidBodyEquations& b, const RigidBodyState& s) {
  const Mat3 r = rotation_matrix(s.attitude());
  return Vec3(s.position()).cross(earth_linear_momentum(b, s)) + r * b.angular_momentum_body(s);
}

RigidBodyState integrate(const RigidBodyEquations& b, RigidBodyState s, Real t_end, int steps,
                         const BodyLoads& constant = {}, const StateDependentLoads& state_loads = nullptr,
                         Real* max_norm_error = nullptr) {
  const Real h = t_end / steps;
  for (int n = 0; n < steps; ++n) {
    const RigidBodyStep st = advance_rk4(b, s, n * h, h, constant, constant, state_loads);
    if (max_norm_error) *max_norm_error = std::max(*max_norm_error, st.quaternion_norm_error);
    s = st.state;
  }
  return s;
}

TEST(Attitude, EulerAnglesRoundTripAndRotationOrderZYX) {
  for (const EulerAngles a : {EulerAngles{0.3, -0.7, 2.1}, EulerAngles{-2.5, 1.2, -0.4}, EulerAngles{0.0, 0.0, 3.0}}) {
    const Quaternion e = quaternion_from_euler(a);
    EXPECT_NEAR(e.norm(), 1.0, 1e-15);
    const EulerAngles b = euler_from_quaternion(e);
    EXPECT_NEAR(b.roll, a.roll, 1e-13);
    EXPECT_NEAR(b.pitch, a.pitch, 1e-13);
    EXPECT_NEAR(b.yaw, a.yaw, 1e-13);
    const Mat3 zyx = (Eigen::AngleAxis<Real>(a.yaw, Vec3::UnitZ()) * Eigen::AngleAxis<Real>(a.pitch, Vec3::UnitY()) *
                      Eigen::AngleAxis<Real>(a.roll, Vec3::UnitX()))
                         .toRotationMatrix();
    EXPECT_LT((rotation_matrix(e) - zyx).norm(), 1e-14);
    // §11.3: down in body axes is the third row of R, (-sin th, cos th sin ph, cos th cos ph)
    const Vec3 down(-std::sin(a.pitch), std::cos(a.pitch) * std::sin(a.roll), std::cos(a.pitch) * std::cos(a.roll));
    EXPECT_LT((down_in_body(e) - down).norm(), 1e-14);
    EXPECT_LT((down_in_body(e) - rotation_matrix(e).row(2).transpose()).norm(), 1e-15);
  }
}

TEST(Attitude, QuaternionRateGivesRdotEqualsRTimesSkewOmega) {
  const Quaternion e = quaternion_from_euler({0.4, 0.3, -1.1});
  const Vec3 w(0.7, -0.2, 0.5);
  const Real dt = 1e-6;
  const Quaternion ed = quaternion_rate(e, w);
  const Mat3 rdot = (rotation_matrix(e + dt * ed) - rotation_matrix(e - dt * ed)) / (2 * dt);
  EXPECT_LT((rdot - rotation_matrix(e) * cross_product_matrix(w)).norm(), 1e-8);
  EXPECT_NEAR(e.dot(ed), 0.0, 1e-15);  // the rate keeps |e| = 1
}

TEST(RigidBody, HydrostaticsAgreeWithTheClassicalEulerAngleTerms) {
  MassProperties mp = tumbling_body(Vec3(0.1, -0.05, 0.2));
  mp.r_b = Vec3(-0.03, 0.02, -0.1);
  mp.weight = 3.0;
  mp.buoyancy = 2.6;
  const RigidBodyEquations body(mp);
  const EulerAngles a{0.35, -0.6, 1.4};
  const BodyLoads h = body.hydrostatic_loads(RigidBodyState::at_rest(Vec3::Zero(), a));
  const Real W = mp.weight, B = mp.buoyancy, cth = std::cos(a.pitch), sth = std::sin(a.pitch);
  const Real cph = std::cos(a.roll), sph = std::sin(a.roll);
  const Vec3 g = mp.r_g, b = mp.r_b;
  EXPECT_NEAR(h.force[0], -(W - B) * sth, 1e-14);
  EXPECT_NEAR(h.force[1], (W - B) * cth * sph, 1e-14);
  EXPECT_NEAR(h.force[2], (W - B) * cth * cph, 1e-14);
  EXPECT_NEAR(h.moment[0], (g[1] * W - b[1] * B) * cth * cph - (g[2] * W - b[2] * B) * cth * sph, 1e-14);
  EXPECT_NEAR(h.moment[1], -(g[0] * W - b[0] * B) * cth * cph - (g[2] * W - b[2] * B) * sth, 1e-14);
  EXPECT_NEAR(h.moment[2], (g[0] * W - b[0] * B) * cth * sph + (g[1] * W - b[1] * B) * sth, 1e-14);
}

TEST(RigidBody, TorqueFreeTumblingConservesEnergyAndMomentaAtFourthOrder) {
  // Origin away from the CG, so every coupling term of M_RB and of the Coriolis part acts.
  const RigidBodyEquations body(tumbling_body(Vec3(0.3, -0.2, 0.1)));
  RigidBodyState s0 = RigidBodyState::at_rest(Vec3(1.0, -2.0, 0.5), {0.2, -0.3, 0.8});
  s0.velocity() = Vec3(0.5, 0.1, -0.2);
  s0.angular_velocity() = Vec3(0.3, 1.1, -0.4);  // near the intermediate axis: a tumbling motion
  const Real e0 = body.kinetic_energy(s0);
  const Vec3 p0 = earth_linear_momentum(body, s0), h0 = earth_angular_momentum(body, s0);
  std::vector<Real> err;
  for (int steps : {200, 400, 800}) {
    Real norm_error = 0.0;
    const RigidBodyState s = integrate(body, s0, 10.0, steps, {}, nullptr, &norm_error);
    const Real e = std::abs(body.kinetic_energy(s) - e0) / e0;
    const Real p = (earth_linear_momentum(body, s) - p0).norm() / p0.norm();
    const Real h = (earth_angular_momentum(body, s) - h0).norm() / h0.norm();
    err.push_back(e + p + h);
    if (steps == 800) {
      EXPECT_LT(norm_error, 1e-10);  // §11.4's health bound, here |w| h ~ 0.015
    }
  }
  for (std::size_t i = 0; i + 1 < err.size(); ++i) {
    const Real order = std::log2(err[i] / err[i + 1]);
    EXPECT_GT(order, 3.7) << "steps " << (200 << i);
    EXPECT_LT(order, 4.5) << "steps " << (200 << i);
  }
}

TEST(RigidBody, TheChoiceOfBodyOriginDoesNotChangeTheMotion) {
  // Body A has its origin at the CG; body B the same body with its origin at G + c.
  // A constant body-axis force at G and a couple move both; G and the attitude agree.
  const Vec3 c(0.4, -0.1, 0.25);
  const RigidBodyEquations a(tumbling_body(Vec3::Zero())), b(tumbling_body(-c));
  BodyLoads load_a{Vec3(0.3, -0.2, 0.5), Vec3(0.05, 0.1, -0.08)};
  BodyLoads load_b{load_a.force, load_a.moment + (-c).cross(load_a.force)};  // moment moved to O_B
  RigidBodyState sa = RigidBodyState::at_rest(Vec3(0, 0, 0), {0.1, 0.2, -0.3});
  sa.velocity() = Vec3(1.0, 0.2, -0.1);
  sa.angular_velocity() = Vec3(0.2, -0.5, 0.7);
  RigidBodyState sb = sa;
  sb.velocity() = sa.velocity() + Vec3(sa.angular_velocity()).cross(c);  // velocity of the point G + c
  sb.position() = Vec3(sa.position()) + rotation_matrix(sa.attitude()) * c;
  sa = integrate(a, sa, 3.0, 3000, load_a);
  sb = integrate(b, sb, 3.0, 3000, load_b);
  EXPECT_LT((Quaternion(sa.attitude()) - Quaternion(sb.attitude())).norm(), 1e-10);
  const Vec3 g_b = Vec3(sb.position()) - rotation_matrix(sb.attitude()) * c;
  EXPECT_LT((Vec3(sa.position()) - g_b).norm(), 1e-10);
}

TEST(RigidBody, NeutrallyBuoyantBodyRollsWithTheHydrostaticPeriod) {
  // W = B, the CG a distance BG below the CB: the CG stays put and the body rolls about it
  // with T = 2 pi sqrt(I_G,x / (W BG)) at small amplitude.
  const Real bg = 0.05;
  MassProperties mp;
  mp.mass = 1.0;
  mp.weight = mp.buoyancy = 1.0;
  mp.r_g = Vec3(0.0, 0.0, bg);  // earth z is down: the CG below the origin (the CB)
  const Mat3 inertia_g = Vec3(0.02, 0.3, 0.3).asDiagonal();
  mp.inertia_o = inertia_g + mp.mass * (bg * bg * Mat3::Identity() - mp.r_g * mp.r_g.transpose());
  const RigidBodyEquations body(mp);
  const Real period = 2.0 * kPi * std::sqrt(inertia_g(0, 0) / (mp.weight * bg));
  RigidBodyState s = RigidBodyState::at_rest(Vec3::Zero(), {0.01, 0.0, 0.0});
  const int per_period = 1000;
  const Real h = period / per_period;
  std::vector<Real> up_crossings;
  Real roll_old = euler_from_quaternion(s.attitude()).roll;
  for (int n = 0; n < 4 * per_period + 10; ++n) {
    s = advance_rk4(body, s, n * h, h, {}, {}).state;
    const Real roll = euler_from_quaternion(s.attitude()).roll;
    if (roll_old < 0.0 && roll >= 0.0) up_crossings.push_back((n + roll_old / (roll_old - roll)) * h);
    roll_old = roll;
  }
  ASSERT_GE(up_crossings.size(), 3u);
  const Real measured = (up_crossings.back() - up_crossings.front()) / (up_crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 1e-4);  // amplitude correction phi0^2/16 = 6e-6
}

TEST(RigidBody, FreeFallUnderConstantNetWeightIsIntegratedExactly) {
  MassProperties mp;
  mp.mass = 1.5;
  mp.inertia_o = Mat3::Identity();
  mp.weight = 3.0;
  mp.buoyancy = 1.2;
  const RigidBodyEquations body(mp);
  // pitched attitude: the body-axis velocity has u and w parts, the path stays vertical
  const RigidBodyState s = integrate(body, RigidBodyState::at_rest(Vec3::Zero(), {0.0, 0.4, 0.0}), 2.0, 7);
  const Real a = (mp.weight - mp.buoyancy) / mp.mass;
  const Vec3 v_earth = rotation_matrix(s.attitude()) * Vec3(s.velocity());
  EXPECT_LT((v_earth - Vec3(0, 0, a * 2.0)).norm(), 1e-13);
  EXPECT_LT((Vec3(s.position()) - Vec3(0, 0, 0.5 * a * 4.0)).norm(), 1e-13);
}

TEST(RigidBody, InterpolatedFlowLoadsAreSecondOrderAndStateLoadsFourthOrder) {
  MassProperties mp;
  mp.mass = 1.0;
  mp.inertia_o = Mat3::Identity();
  const RigidBodyEquations body(mp);
  const Real t_end = 2.0;  // X(t) = cos t from rest: u(T) = sin T
  auto error = [&](int steps, bool as_flow_loads) {
    RigidBodyState s = RigidBodyState::at_rest(Vec3::Zero(), {});
    const Real h = t_end / steps;
    for (int n = 0; n < steps; ++n) {
      const Real t = n * h;
      if (as_flow_loads) {  // known at the flow levels only, as from the CFD
        s = advance_rk4(body, s, t, h, {Vec3(std::cos(t), 0, 0), Vec3::Zero()},
                        {Vec3(std::cos(t + h), 0, 0), Vec3::Zero()})
                .state;
      } else {
        s = advance_rk4(body, s, t, h, {}, {},
                        [](const RigidBodyState&, Real time) { return BodyLoads{Vec3(std::cos(time), 0, 0), Vec3::Zero()}; })
                .state;
      }
    }
    return std::abs(s.velocity()[0] - std::sin(t_end));
  };
  const Real flow_order = std::log2(error(20, true) / error(40, true));
  const Real exact_order = std::log2(error(20, false) / error(40, false));
  EXPECT_NEAR(flow_order, 2.0, 0.15);
  EXPECT_NEAR(exact_order, 4.0, 0.3);
}

TEST(RigidBody, UnphysicalMassPropertiesAreRejectedWithTheirName) {
  MassProperties mp = tumbling_body(Vec3::Zero());
  mp.mass = 0.0;
  try {
    RigidBodyEquations b(mp);
    FAIL() << "zero mass accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mass"), std::string::npos);
  }
  mp = tumbling_body(Vec3::Zero());
  mp.r_g = Vec3(0, 0, 5.0);  // the stated I_O cannot belong to a body with its CG 5 away
  try {
    RigidBodyEquations b(mp);
    FAIL() << "inertia inconsistent with the CG offset accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("centre of gravity"), std::string::npos);
  }
  mp = tumbling_body(Vec3::Zero());
  mp.down = Vec3(0.0, 0.0, 2.0);
  EXPECT_THROW(RigidBodyEquations{mp}, Error);
  AccelerationOptions o;
  o.added_mass_estimate(0, 0) = -1.0;
  EXPECT_THROW(RigidBodyEquations(tumbling_body(Vec3::Zero()), o), Error);
}

TEST(RigidBody, GravityAlongAnyDownDirectionGivesTheSameMotionTurned) {
  // The same release in NED earth axes and in axes turned about x by 90 degrees (down =
  // -y there): positions and attitudes correspond under the turn.
  MassProperties ned = tumbling_body(Vec3(0.1, -0.2, 0.3));
  ned.weight = 3.0;
  ned.buoyancy = 1.0;
  ned.r_b = Vec3(0.0, 0.1, -0.1);
  MassProperties turned = ned;
  const Mat3 q = Eigen::AngleAxis<Real>(kPi / 2, Vec3::UnitX()).toRotationMatrix();
  turned.down = q * Vec3::UnitZ();
  const RigidBodyEquations a(ned), b(turned);
  RigidBodyState sa = RigidBodyState::at_rest(Vec3::Zero(), EulerAngles{0.2, 0.1, -0.3}), sb = sa;
  sb.attitude() = quaternion_from_rotation(q * rotation_matrix(sa.attitude()));
  sa = integrate(a, sa, 2.0, 200);
  sb = integrate(b, sb, 2.0, 200);
  // Round-off apart (200 steps of a tumbling body whose position has moved by ~2).
  EXPECT_LT((q * Vec3(sa.position()) - Vec3(sb.position())).norm(), 1e-10);
  EXPECT_LT((q * rotation_matrix(sa.attitude()) - rotation_matrix(sb.attitude())).norm(), 1e-10);
  EXPECT_LT((sa.y.head<6>() - sb.y.head<6>()).norm(), 1e-10);  // body-axis velocities agree
  EXPECT_GT(Vec3(sb.position()).norm(), 0.5);
}

}  // namespace
}  // namespace narwhal

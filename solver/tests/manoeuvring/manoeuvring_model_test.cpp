// The manoeuvring model's loads (manoeuvring/manoeuvring_model.hpp): each coefficient
// multiplies its own term, half of it in flow units; a body flown by RK4 under a linear
// model settles into the steady turn the linear equations give; the acceleration
// derivatives make the added mass.
#include <gtest/gtest.h>

#include <cmath>

#include "manoeuvring/linear_turn.hpp"
#include "manoeuvring/manoeuvring_model.hpp"
#include "motion/rk4.hpp"

namespace narwhal {
namespace {

const Vec6 kNu = (Vec6() << 0.9, 0.1, -0.2, 0.05, 0.03, -0.04).finished();
const suboff::Deflections kDeflections{0.1, -0.05, 0.02};  // rudder, stern planes, sail planes

TEST(ManoeuvringModel, EachCoefficientMultipliesItsTerm) {
  struct Case {
    const char* name;
    int component;  // 0-2 force, 3-5 moment
    Real term;      // at kNu, kDeflections
  };
  const Real u = 0.9, v = 0.1, w = -0.2, p = 0.05, q = 0.03, r = -0.04;
  const Case cases[] = {{"Xuu", 0, u * u},           {"Xvv", 0, v * v},
                        {"Xrr", 0, r * r},           {"Xdrdr", 0, u * u * 0.01},
                        {"Yv", 1, u * v},            {"Yr", 1, u * r},
                        {"Yvv", 1, v * std::abs(v)}, {"Ydr", 1, u * u * 0.1},
                        {"Z0", 2, u * u},            {"Zw", 2, u * w},
                        {"Zq", 2, u * q},            {"Zww", 2, w * std::abs(w)},
                        {"Zds", 2, u * u * -0.05},   {"Zdb", 2, u * u * 0.02},
                        {"Kp", 3, u * p},            {"Mw", 4, u * w},
                        {"Mq", 4, u * q},            {"Mds", 4, u * u * -0.05},
                        {"Nv", 5, u * v},            {"Nr", 5, u * r},
                        {"Ndr", 5, u * u * 0.1}};
  for (const Case& k : cases) {
    ManoeuvringCoefficients c;
    bool found = false;
    for (auto& [name, value] : c.named())
      if (name == k.name) {
        *value = 1.7;
        found = true;
      }
    ASSERT_TRUE(found) << k.name;
    const BodyLoads l = hydrodynamic_loads(c, kNu, kDeflections);
    Vec6 all;
    all << l.force, l.moment;
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(all[i], i == k.component ? 0.5 * 1.7 * k.term : 0.0, 1e-15) << k.name << " component " << i;
  }
}

TEST(ManoeuvringModel, AccelerationDerivativesMakeTheAddedMass) {
  ManoeuvringCoefficients c;
  c.Xudot = -0.0008;
  c.Yvdot = -0.016;
  c.Yrdot = 0.0004;
  c.Nvdot = 0.0002;
  c.Nrdot = -0.0009;
  const Mat6 m = added_mass(c);
  EXPECT_EQ(m(0, 0), 0.0004);
  EXPECT_EQ(m(1, 1), 0.008);
  EXPECT_EQ(m(5, 5), 0.00045);
  EXPECT_DOUBLE_EQ(m(1, 5), -0.00015);
  EXPECT_EQ(m(1, 5), m(5, 1));
}

TEST(ManoeuvringModel, ALinearModelSettlesIntoTheLinearSteadyTurn) {
  // Surge held at u = 1, no gravity (linear_turn.hpp).
  const ManoeuvringCoefficients c = test::linear_turning_coefficients();
  MassProperties mp;
  mp.mass = 0.0085;
  mp.inertia_o = Vec3(1.5e-5, 4.85e-4, 4.85e-4).asDiagonal();
  AccelerationOptions o;
  o.free = {false, true, false, false, false, true};
  o.added_mass_estimate = added_mass(c);
  const RigidBodyEquations body(mp, o);
  const Real dr = 10.0 * std::acos(-1.0) / 180.0;
  const suboff::Deflections d{dr, 0.0, 0.0};
  const StateDependentLoads loads = [&](const RigidBodyState& s, Real) {
    Vec6 nu;
    nu << s.velocity(), s.angular_velocity();
    return hydrodynamic_loads(c, nu, d);
  };
  RigidBodyState s = RigidBodyState::at_rest(Vec3::Zero(), EulerAngles{});
  s.velocity()[0] = 1.0;
  for (int n = 0; n < 6000; ++n) s = advance_rk4(body, s, n * 0.01, 0.01, BodyLoads{}, BodyLoads{}, loads).state;
  const Eigen::Vector2d steady = test::linear_steady_turn(c, mp.mass, dr);
  // By t = 60 the transient has decayed below 1e-7 of the turn.
  EXPECT_NEAR(s.velocity()[1], steady[0], 1e-7 * std::abs(steady[0]));
  EXPECT_NEAR(s.angular_velocity()[2], steady[1], 1e-7 * std::abs(steady[1]));
  EXPECT_LT(steady[1], 0.0);  // rudder > 0 (trailing edges to port) turns the nose to port
}

}  // namespace
}  // namespace narwhal

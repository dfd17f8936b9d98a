// The zig-zag manoeuvre (control/zigzag.hpp) on a toy vehicle whose yaw and pitch answer
// their surfaces with the real signs (rudder > 0 turns the nose to port, stern planes > 0
// put it down): the surface reverses each time the attitude passes the switching angle
// the way the deflection drives it, turns no faster than its rate, and a restored
// manoeuvre continues exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "control/zigzag.hpp"
#include "core/error.hpp"

namespace narwhal {
namespace {

constexpr Real kDegree = 3.14159265358979323846 / 180.0;

struct ToyVehicle {
  Real pitch = 0.0, q = 0.0, heading = 0.0, r = 0.0;
  void step(const suboff::Deflections& d, Real dt) {
    q += (-0.02 * d.stern_planes - 0.02 * q) / 0.01 * dt;
    pitch += q * dt;
    r += (-0.02 * d.rudder - 0.02 * r) / 0.01 * dt;
    heading += r * dt;
  }
  VehicleReading reading() const { return {0.0, 0.0, pitch, q, heading, r}; }
};

ZigzagSettings ten_ten(ZigzagSettings::Surface s) {
  return {.surface = s, .angle = 10.0 * kDegree, .switch_at = 10.0 * kDegree, .start = 0.5, .rate = 0.0, .first = 1};
}

// Flies `steps` steps of dt; per step the surface's angle and the attitude it drives.
struct Flight {
  std::vector<Real> surface, attitude;
};
Flight fly(Zigzag& z, ToyVehicle& v, suboff::Deflections& d, int first_step, int steps, Real dt, bool rudder) {
  Flight f;
  for (int n = first_step; n < first_step + steps; ++n) {
    d = z.command((n + 1) * dt, dt, v.reading(), d);
    v.step(d, dt);
    f.surface.push_back(rudder ? d.rudder : d.stern_planes);
    f.attitude.push_back(rudder ? v.heading : v.pitch);
  }
  return f;
}

TEST(Zigzag, TheRudderReversesWhenTheHeadingPassesTheSwitchingAngle) {
  Zigzag z(ten_ten(ZigzagSettings::Surface::Rudder));
  ToyVehicle v;
  suboff::Deflections d;
  const Real dt = 0.01;
  const Flight f = fly(z, v, d, 0, 3000, dt, true);
  EXPECT_EQ(f.surface[48], 0.0);  // t = 0.49: before the start
  EXPECT_NEAR(f.surface[49], 10.0 * kDegree, 1e-15);
  EXPECT_EQ(d.stern_planes, 0.0);
  // Each reversal happens in the step after the heading passed +-10 degrees the way the
  // rudder drove it (rudder > 0: towards port, negative heading).
  int reversals = 0;
  for (std::size_t n = 50; n < f.surface.size(); ++n) {
    if (f.surface[n] == f.surface[n - 1]) continue;
    ++reversals;
    const Real drove = -f.surface[n - 1] / (10.0 * kDegree);  // the sign of the heading it drove towards
    EXPECT_GE(drove * f.attitude[n - 1], 10.0 * kDegree) << "step " << n;
    EXPECT_LT(drove * f.attitude[n - 2], 10.0 * kDegree) << "step " << n;
  }
  EXPECT_GE(reversals, 3);
  EXPECT_EQ(reversals, z.reversals());
  // It overshoots the switching angle (the vehicle keeps turning while the rudder reverses).
  EXPECT_GT(*std::max_element(f.attitude.begin(), f.attitude.end()), 10.0 * kDegree);
}

TEST(Zigzag, TheSternPlanesTurnNoFasterThanTheirRate) {
  ZigzagSettings s = ten_ten(ZigzagSettings::Surface::SternPlanes);
  s.rate = 4.0 * kDegree;  // per unit time: 2.5 time units from 0 to 10 degrees
  s.first = -1;            // nose up first
  Zigzag z(s);
  ToyVehicle v;
  suboff::Deflections d;
  const Real dt = 0.01;
  const Flight f = fly(z, v, d, 0, 4000, dt, false);
  EXPECT_NEAR(f.surface[49], -0.04 * kDegree, 1e-15);
  for (std::size_t n = 1; n < f.surface.size(); ++n)
    EXPECT_LE(std::abs(f.surface[n] - f.surface[n - 1]), 4.0 * kDegree * dt * (1 + 1e-12)) << "step " << n;
  EXPECT_GT(*std::max_element(f.attitude.begin(), f.attitude.end()), 10.0 * kDegree);  // nose up past 10 first
  EXPECT_GE(z.reversals(), 2);
  EXPECT_EQ(d.rudder, 0.0);
}

TEST(Zigzag, ARestoredManoeuvreContinuesExactly) {
  const Real dt = 0.01;
  Zigzag whole(ten_ten(ZigzagSettings::Surface::Rudder));
  ToyVehicle vw;
  suboff::Deflections dw;
  fly(whole, vw, dw, 0, 700, dt, true);
  Zigzag restored(ten_ten(ZigzagSettings::Surface::Rudder));
  restored.restore(whole.checkpoint());
  ToyVehicle vr = vw;
  suboff::Deflections dr = dw;
  const Flight a = fly(whole, vw, dw, 700, 1500, dt, true), b = fly(restored, vr, dr, 700, 1500, dt, true);
  EXPECT_EQ(a.surface, b.surface);
  EXPECT_EQ(a.attitude, b.attitude);
  EXPECT_THROW(restored.restore({1.0}), Error);
}

TEST(Zigzag, NonsenseSettingsAreRefused) {
  ZigzagSettings s = ten_ten(ZigzagSettings::Surface::Rudder);
  s.angle = 0.0;
  EXPECT_THROW(Zigzag{s}, Error);
  s = ten_ten(ZigzagSettings::Surface::Rudder);
  s.first = 2;
  EXPECT_THROW(Zigzag{s}, Error);
  s = ten_ten(ZigzagSettings::Surface::Rudder);
  s.rate = -1.0;
  EXPECT_THROW(Zigzag{s}, Error);
}

}  // namespace
}  // namespace narwhal

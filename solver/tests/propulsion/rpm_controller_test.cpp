// The rpm controller (self-propulsion): on a model vehicle whose resistance rises with
// the thrust (a thrust deduction the controller does not know), n settles where T = R.
#include <gtest/gtest.h>

#include <cmath>

#include "io/table_file.hpp"
#include "propulsion/body_force_propulsor.hpp"
#include "propulsion/rpm_controller.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

TEST(RpmController, SettlesWhereThrustBalancesAResistanceThatRisesWithIt) {
  // T = K_T n^2 D^4 at a fixed advance ratio's K_T; R = R0 + t T (thrust deduction t).
  const Real k = 0.15, R0 = 0.05, t = 0.2;
  auto thrust = [&](Real n) { return k * n * n; };
  RpmControlSettings s;
  s.interval = 5;
  RpmController c(s);
  Real n = 0.3;
  int cycle = 0;
  for (; cycle < 400 && !c.settled(); ++cycle) {
    const Real T = thrust(n), R = R0 + t * T;
    const Real next = c.update(cycle, n, T, R, 2.0 * k * n);
    if (cycle % s.interval != 0) {
      EXPECT_EQ(next, n) << "n moves only every interval cycles";
    }
    EXPECT_LE(std::abs(next - n), s.max_change * n * (1 + 1e-12));
    n = next;
  }
  ASSERT_TRUE(c.settled()) << "after " << cycle << " cycles, surplus " << c.surplus();
  const Real exact = std::sqrt(R0 / ((1.0 - t) * k));
  EXPECT_NEAR(n / exact, 1.0, s.tolerance);
  EXPECT_LT(c.steps(), 20);
}

TEST(RpmController, WaitsForAResistanceAndRestoresItsState) {
  RpmController c(RpmControlSettings{});
  EXPECT_EQ(c.update(10, 1.0, 0.1, 0.0, 0.2), 1.0);
  EXPECT_FALSE(c.settled());
  const Real moved = c.update(20, 1.0, 0.1, 0.2, 0.2);
  EXPECT_GT(moved, 1.0);
  RpmController d(RpmControlSettings{});
  d.restore(c.state());
  EXPECT_EQ(d.steps(), 1);
  EXPECT_EQ(d.update(25, moved, 0.1, 0.2, 0.2), moved) << "the restored controller waits out its interval";
  EXPECT_THROW(c.update(40, 1.0, 0.1, 0.2, -0.1), Error);
}

TEST(BodyForcePropulsor, ThrustSlopeIsTheDerivativeAtTheAdvanceSpeed) {
  PropulsorSpec s;
  s.disk = {0.1, 0.5, 0.1};
  s.rps = 1.2;
  BodyForcePropulsor p(s, std::make_shared<OpenWaterTable>(
                              Table::read(test::source_path("reference_data/propulsor/dtmb4119_open_water_openprop.csv"))));
  p.set_surge_speed(1.0);
  const Real slope = p.thrust_slope(), h = 1e-5;
  p.set_rps(1.2 + h);
  const Real up = p.loads().thrust;
  p.set_rps(1.2 - h);
  const Real down = p.loads().thrust;
  EXPECT_NEAR(slope, (up - down) / (2 * h), 1e-6 * std::abs(slope));
  EXPECT_DOUBLE_EQ(p.loads().advance_speed, 1.0) << "n changes J, not V_A";
}

}  // namespace
}  // namespace narwhal

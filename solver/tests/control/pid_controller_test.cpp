// The autopilots' PID controller (control/pid_controller.hpp): output limits, rate
// limit, anti-windup, a closed loop that settles without steady error, and restarts.
#include <gtest/gtest.h>

#include <cmath>

#include "control/pid_controller.hpp"
#include "core/error.hpp"

namespace narwhal {
namespace {

TEST(PidController, ProportionalWithinItsLimits) {
  PidController c({.kp = 2.0, .min_output = -1.0, .max_output = 1.5});
  EXPECT_DOUBLE_EQ(c.update(0.3, 0.0, 0.1), 0.6);
  EXPECT_DOUBLE_EQ(c.update(5.0, 0.0, 0.1), 1.5);
  EXPECT_DOUBLE_EQ(c.update(-5.0, 0.0, 0.1), -1.0);
}

TEST(PidController, DerivativeFromTheMeasuredRateAndIntegralOfTheError) {
  PidController c({.kp = 1.0, .ki = 0.5, .kd = 2.0});
  EXPECT_DOUBLE_EQ(c.update(1.0, -0.25, 0.2), 1.0 + 0.5 * 0.2 - 0.5);
  EXPECT_DOUBLE_EQ(c.update(1.0, 0.0, 0.2), 1.0 + 0.5 * 0.4);
  EXPECT_DOUBLE_EQ(c.integral(), 0.4);
}

TEST(PidController, ACommandStepMovesTheSurfaceAtItsRateLimit) {
  PidController c({.kp = 10.0, .min_output = -30.0, .max_output = 30.0, .max_rate = 5.0});
  for (int n = 1; n <= 8; ++n) EXPECT_NEAR(c.update(2.0, 0.0, 0.5), std::min(2.5 * n, 20.0), 1e-12) << n;
}

TEST(PidController, ASaturatedOutputDoesNotWindTheIntegralUp) {
  // Held at its limit by a large error for a long time, then the error reverses: the
  // integral has not grown while held, so the output leaves the limit at once.
  PidSettings s{.kp = 1.0, .ki = 1.0, .min_output = -1.0, .max_output = 1.0};
  PidController c(s);
  for (int n = 0; n < 100; ++n) c.update(5.0, 0.0, 0.1);
  EXPECT_EQ(c.output(), 1.0);
  EXPECT_LT(c.integral(), 0.5);  // grew only until the output reached the limit
  EXPECT_LT(c.update(-1.0, 0.0, 0.1), 1.0);
  // An error that pulls the output back is integrated even while it is held.
  PidController d(s);
  d.restore({10.0, 1.0});
  d.update(-0.5, 0.0, 0.1);
  EXPECT_DOUBLE_EQ(d.integral(), 10.0 - 0.05);
}

TEST(PidController, HoldsAFirstOrderPlantAtItsCommandWithoutSteadyError) {
  // y' = -y + u + d with a constant disturbance d = -0.3: the integral removes the
  // steady error a proportional controller would leave (d / (1 + kp)).
  PidController c({.kp = 2.0, .ki = 1.5, .min_output = -2.0, .max_output = 2.0, .max_rate = 4.0});
  Real y = 0.0;
  const Real dt = 0.01, command = 1.0;
  for (int n = 0; n < 3000; ++n) {
    const Real rate = -y + c.output() - 0.3;
    const Real u = c.update(command - y, -rate, dt);
    y += dt * (-y + u - 0.3);
  }
  EXPECT_NEAR(y, command, 1e-6);
  EXPECT_NEAR(c.output(), 1.3, 1e-5);
}

TEST(PidController, ARestoredControllerContinuesExactly) {
  const PidSettings s{.kp = 1.2, .ki = 0.7, .kd = 0.3, .min_output = -1.0, .max_output = 1.0, .max_rate = 2.0};
  PidController whole(s), first(s);
  for (int n = 0; n < 20; ++n) {
    whole.update(std::sin(0.3 * n), std::cos(0.3 * n), 0.05);
    if (n < 10) first.update(std::sin(0.3 * n), std::cos(0.3 * n), 0.05);
  }
  PidController second(s);
  second.restore(first.state());
  for (int n = 10; n < 20; ++n) second.update(std::sin(0.3 * n), std::cos(0.3 * n), 0.05);
  EXPECT_EQ(second.output(), whole.output());
  EXPECT_EQ(second.integral(), whole.integral());
}

TEST(PidController, RefusesLimitsThatCannotHold) {
  EXPECT_THROW(PidController({.min_output = 1.0, .max_output = -1.0}), Error);
  EXPECT_THROW(PidController({.max_rate = 0.0}), Error);
  EXPECT_THROW(PidController({.min_output = -1.0, .max_output = 1.0, .initial_output = 2.0}), Error);
  EXPECT_THROW(PidController({.kp = std::nan("")}), Error);
  PidController c({.min_output = -1.0, .max_output = 1.0});
  EXPECT_THROW(c.update(1.0, 0.0, 0.0), Error);
  EXPECT_THROW(c.restore({0.0, 3.0}), Error);
}

}  // namespace
}  // namespace narwhal

#pragma once
// A PID controller for the autopilots (issue 19): depth, pitch and heading held by the
// stern planes, sail planes and rudders. Its output (a control surface's deflection) is
// kept within limits and moves no faster than a rate limit, as a real actuator does, and
// the integral stops growing while the output is held at a limit by an error that pushes
// further into it (anti-windup by conditional integration), so that a long saturation
// does not leave a wound-up integral to overshoot with.
//
// The derivative term takes the error's rate from a measured rate (a pitch rate for a
// pitch error) rather than differencing the error, so that a step in the command gives
// no derivative kick.
//
// Usage:
//   PidController pitch({.kp = 2.0, .ki = 0.2, .kd = 1.0, .min_output = -20, .max_output = 20, .max_rate = 10});
//   const Real stern_planes = pitch.update(theta_command - theta, -q, dt);
#include <limits>

#include "core/types.hpp"

namespace narwhal {

struct PidSettings {
  Real kp = 0.0, ki = 0.0, kd = 0.0;
  Real min_output = -std::numeric_limits<Real>::infinity();
  Real max_output = std::numeric_limits<Real>::infinity();
  Real max_rate = std::numeric_limits<Real>::infinity();  // |d output / dt|
  Real initial_output = 0.0;                               // the surface's deflection at the start
};

class PidController {
 public:
  // Throws Error unless the gains are finite, min_output < max_output, the rate limit is
  // positive and the initial output lies within the limits.
  explicit PidController(PidSettings s);

  // One step of length dt > 0 with error e = command - measured and its rate de/dt;
  // returns the new output: kp e + ki int e dt + kd de/dt, limited in value and rate.
  Real update(Real error, Real error_rate, Real dt);

  Real output() const { return output_; }
  Real integral() const { return integral_; }
  const PidSettings& settings() const { return s_; }

  // What a restart carries to continue exactly.
  struct State {
    Real integral = 0.0;
    Real output = 0.0;
  };
  State state() const { return {integral_, output_}; }
  void restore(const State& s);

 private:
  PidSettings s_;
  Real integral_ = 0.0;
  Real output_ = 0.0;
};

}  // namespace narwhal

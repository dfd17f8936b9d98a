#include "control/pid_controller.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace narwhal {

PidController::PidController(PidSettings s) : s_(s), output_(s.initial_output) {
  if (!std::isfinite(s.kp) || !std::isfinite(s.ki) || !std::isfinite(s.kd))
    fail("PID controller: the gains must be finite, got kp {}, ki {}, kd {}", s.kp, s.ki, s.kd);
  if (!(s.min_output < s.max_output))
    fail("PID controller: the lower output limit ({}) must lie below the upper ({})", s.min_output, s.max_output);
  if (!(s.max_rate > 0.0)) fail("PID controller: the rate limit must be positive, got {}", s.max_rate);
  if (!(s.initial_output >= s.min_output && s.initial_output <= s.max_output))
    fail("PID controller: the initial output {} lies outside the limits [{}, {}]", s.initial_output, s.min_output,
         s.max_output);
}

Real PidController::update(Real error, Real error_rate, Real dt) {
  if (!(dt > 0.0)) fail("PID controller: the step must be positive, got {}", dt);
  const Real integral = integral_ + error * dt;
  const Real wanted = s_.kp * error + s_.ki * integral + s_.kd * error_rate;
  const Real reach = s_.max_rate * dt;
  const Real held = std::clamp(wanted, std::max(s_.min_output, output_ - reach), std::min(s_.max_output, output_ + reach));
  // Anti-windup: while a limit holds the output, integrate only errors that pull it back.
  if (held == wanted || (wanted - held) * (s_.ki * error) <= 0.0) integral_ = integral;
  output_ = held;
  return output_;
}

void PidController::restore(const State& s) {
  if (!(s.output >= s_.min_output && s.output <= s_.max_output))
    fail("PID controller: a restart's output {} lies outside the limits [{}, {}]", s.output, s_.min_output,
         s_.max_output);
  integral_ = s.integral;
  output_ = s.output;
}

}  // namespace narwhal

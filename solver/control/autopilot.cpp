#include "control/autopilot.hpp"

#include "core/error.hpp"

namespace narwhal {

Autopilot::Autopilot(AutopilotSettings s)
    : s_(std::move(s)), heading_(s_.heading_loop), pitch_(s_.pitch_loop), depth_(s_.depth_loop) {
  if (s_.sail_plane_loop) sail_.emplace(*s_.sail_plane_loop);
  if (s_.depth_change && s_.pitch)
    fail("autopilot: a depth command sets the pitch command itself; give one of depth_change and pitch");
  if (s_.sail_plane_loop && !s_.depth_change) fail("autopilot: the sail planes' loop needs a depth command");
  pitch_command_ = s_.pitch.value_or(0.0);
}

suboff::Deflections Autopilot::command(const VehicleReading& now, Real dt, const suboff::Deflections& present) {
  suboff::Deflections d = present;
  if (s_.heading) d.rudder = -heading_.update(*s_.heading - now.heading, -now.heading_rate, dt);
  if (s_.depth_change) {
    const Real error = *s_.depth_change - now.depth, rate = -now.depth_rate;
    // Deeper wanted: the nose down (a negative pitch command), the sail planes' trailing
    // edges up.
    pitch_command_ = -depth_.update(error, rate, dt);
    if (sail_) d.sail_planes = -sail_->update(error, rate, dt);
  }
  if (s_.depth_change || s_.pitch)
    d.stern_planes = -pitch_.update(pitch_command_ - now.pitch, -now.pitch_rate, dt);
  return d;
}

std::vector<Real> Autopilot::checkpoint() const {
  std::vector<Real> v;
  v.reserve(9);
  auto keep = [&](const PidController& c) {
    v.push_back(c.integral());
    v.push_back(c.output());
  };
  keep(heading_);
  keep(pitch_);
  keep(depth_);
  if (sail_) keep(*sail_);
  v.push_back(pitch_command_);
  return v;
}

void Autopilot::restore(const std::vector<Real>& v) {
  const std::size_t expected = sail_ ? 9 : 7;
  if (v.size() != expected)
    fail("restart: its autopilot state has {} values, this case's autopilot {}", v.size(), expected);
  heading_.restore({v[0], v[1]});
  pitch_.restore({v[2], v[3]});
  depth_.restore({v[4], v[5]});
  if (sail_) sail_->restore({v[6], v[7]});
  pitch_command_ = v.back();
}

}  // namespace narwhal

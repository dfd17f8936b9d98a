#include "app/control_surfaces.hpp"

#include <cmath>

#include "core/error.hpp"
#include "motion/attitude.hpp"

namespace narwhal {

namespace {

bool same(const suboff::Deflections& a, const suboff::Deflections& b) {
  return a.rudder == b.rudder && a.stern_planes == b.stern_planes && a.sail_planes == b.sail_planes;
}

}  // namespace

VehicleReading read_vehicle(const RigidMotionSample& m) {
  // Body axes at release: B0 = diag(-1, -1, 1) of the grid's (grid_axes.hpp); now R B0.
  const Mat3 b0 = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  const Mat3 body = m.pose.rotation * b0;
  const EulerAngles a = euler_from_quaternion(quaternion_from_rotation(b0.transpose() * body));
  const Vec3 w = body.transpose() * m.angular_velocity;  // p, q, r
  const Real sf = std::sin(a.roll), cf = std::cos(a.roll);
  VehicleReading r;
  r.depth = m.pose.displacement[2];
  r.depth_rate = m.velocity[2];
  r.pitch = a.pitch;
  r.pitch_rate = w[1] * cf - w[2] * sf;  // NUMERICS §11.4's Euler rates
  r.heading = a.yaw;
  r.heading_rate = (w[1] * sf + w[2] * cf) / std::cos(a.pitch);
  return r;
}

ControlSurfaces::ControlSurfaces(const CaseConfig& c, int split_for, int levels, bool pieces)
    : shapes_(c, split_for, levels, pieces),
      angles_(shapes_.as_built()),
      previous_(angles_),
      shaped_(angles_) {
  if (c.controls) schedule_.emplace(*c.controls);
  if (c.autopilot) autopilot_.emplace(*c.autopilot);
  if (c.zigzag) zigzag_.emplace(*c.zigzag);
}

bool ControlSurfaces::reshape(const suboff::Deflections& d, RunMotion& motion) {
  if (same(d, shaped_)) return false;
  motion.reshape_all(shapes_.at(d));
  shaped_ = d;
  return true;
}

bool ControlSurfaces::start(RunMotion& motion) {
  if (schedule_) angles_ = schedule_->at(0.0, shapes_.as_built());
  previous_ = angles_;
  return reshape(angles_, motion);
}

bool ControlSurfaces::begin_step(Real t_next, Real dt, const VehicleReading& now, RunMotion& motion) {
  previous_ = angles_;
  if (schedule_) angles_ = schedule_->at(t_next, angles_);
  if (autopilot_) angles_ = autopilot_->command(now, dt, angles_);
  if (zigzag_) angles_ = zigzag_->command(t_next, dt, now, angles_);
  return reshape(angles_, motion);
}

std::vector<Real> ControlSurfaces::checkpoint() const {
  std::vector<Real> v{previous_.rudder, previous_.stern_planes, previous_.sail_planes,
                      angles_.rudder,   angles_.stern_planes,   angles_.sail_planes};
  if (autopilot_)
    for (Real x : autopilot_->checkpoint()) v.push_back(x);
  if (zigzag_)
    for (Real x : zigzag_->checkpoint()) v.push_back(x);  // last: its length is fixed
  return v;
}

void ControlSurfaces::restore(const std::vector<Real>& v) {
  if (v.empty())
    fail("restart: it holds no control-surface state (written by a run without [controls], [autopilot] or [zigzag]); "
         "a dual-time run that turns its surfaces continues only from its own restarts");
  const std::size_t zigzag_values = zigzag_ ? zigzag_->checkpoint().size() : 0;
  if (v.size() < 6 + zigzag_values)
    fail("restart: its control-surface state has {} values, at least {} expected", v.size(), 6 + zigzag_values);
  previous_ = {v[0], v[1], v[2]};
  angles_ = {v[3], v[4], v[5]};
  const std::vector<Real> pilot(v.begin() + 6, v.end() - static_cast<std::ptrdiff_t>(zigzag_values));
  if (autopilot_) autopilot_->restore(pilot);
  else if (!pilot.empty()) fail("restart: it holds an autopilot's state; this case has no [autopilot]");
  if (zigzag_) zigzag_->restore(std::vector<Real>(v.end() - static_cast<std::ptrdiff_t>(zigzag_values), v.end()));
}

}  // namespace narwhal

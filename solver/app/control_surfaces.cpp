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
      law_(c.controls, c.autopilot, c.zigzag, shapes_.as_built()),
      shaped_(shapes_.as_built()) {}

bool ControlSurfaces::reshape(const suboff::Deflections& d, RunMotion& motion) {
  if (same(d, shaped_)) return false;
  motion.reshape_all(shapes_.at(d));
  shaped_ = d;
  return true;
}

bool ControlSurfaces::start(RunMotion& motion) {
  law_.start();
  return reshape(law_.angles(), motion);
}

bool ControlSurfaces::begin_step(Real t_next, Real dt, const VehicleReading& now, RunMotion& motion) {
  law_.begin_step(t_next, dt, now);
  return reshape(law_.angles(), motion);
}

}  // namespace narwhal

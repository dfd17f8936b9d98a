#include "control/vehicle_reading.hpp"

#include <cmath>

#include "motion/attitude.hpp"

namespace narwhal {

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

}  // namespace narwhal

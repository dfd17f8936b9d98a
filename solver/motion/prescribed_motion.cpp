#include "motion/prescribed_motion.hpp"

#include <cmath>

namespace narwhal {

int parse_dof(const std::string& name) {
  static const char* names[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  for (int d = 0; d < 6; ++d)
    if (name == names[d]) return d;
  return -1;
}

std::array<Real, 6> PrescribedMotion::coordinates(Real t, bool rates) const {
  std::array<Real, 6> q{};
  for (int d = 0; d < 3; ++d) q[d] = rates ? s_.velocity[d] : s_.velocity[d] * t;
  for (const Oscillation& o : s_.oscillations) {
    const Real arg = o.angular_frequency * t + o.phase;
    q[o.dof] += rates ? o.amplitude * o.angular_frequency * std::cos(arg) : o.amplitude * std::sin(arg);
  }
  return q;
}

namespace {
Mat3 about(int axis, Real angle) { return Eigen::AngleAxis<Real>(angle, Vec3::Unit(axis)).toRotationMatrix(); }
}  // namespace

RigidPose PrescribedMotion::pose(Real t) const {
  const auto q = coordinates(t, false);
  return RigidPose{about(2, q[5]) * about(1, q[4]) * about(0, q[3]), Vec3(q[0], q[1], q[2])};
}

Vec3 PrescribedMotion::velocity(Real t) const {
  const auto r = coordinates(t, true);
  return Vec3(r[0], r[1], r[2]);
}

Vec3 PrescribedMotion::angular_velocity(Real t) const {
  // R = Rz(psi) Ry(theta) Rx(phi): omega = psi' e_z + theta' Rz e_y + phi' Rz Ry e_x.
  const auto q = coordinates(t, false);
  const auto r = coordinates(t, true);
  const Mat3 rz = about(2, q[5]);
  return r[5] * Vec3::UnitZ() + r[4] * (rz * Vec3::UnitY()) + r[3] * (rz * about(1, q[4]) * Vec3::UnitX());
}

}  // namespace narwhal

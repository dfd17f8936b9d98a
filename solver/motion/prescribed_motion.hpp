#pragma once
// A prescribed rigid motion of the whole grid ([motion] type = "prescribed"): a constant
// velocity plus sinusoids in any of the six degrees of freedom, in grid axes, about a
// pivot. Translations add up along x, y, z; the angles about the grid's x, y and z axes
// (roll, pitch, yaw) compose as R = R_z(yaw) R_y(pitch) R_x(roll).
//
//   [motion]
//   type = "prescribed"
//   pivot = [0.0, 0.0, 0.0]
//   velocity = [-1.0, 0.0, 0.0]          # constant translation
//   [[motion.oscillation]]
//   dof = "z"                            # x, y, z, roll, pitch or yaw
//   amplitude = 0.05                     # length, or degrees for the angles
//   angular_frequency = 6.2832           # rad per unit time
//   phase = 0.0                          # degrees
#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "motion/grid_motion.hpp"

namespace narwhal {

struct Oscillation {
  int dof = 0;  // 0-2: translation along x, y, z; 3-5: rotation about x, y, z
  Real amplitude = 0.0;  // length; radians for rotations
  Real angular_frequency = 0.0;
  Real phase = 0.0;  // radians
};

struct PrescribedMotionSpec {
  Vec3 pivot = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  std::vector<Oscillation> oscillations;
};

// "x" ... "yaw" -> 0 ... 5; -1 when unknown.
int parse_dof(const std::string& name);

class PrescribedMotion {
 public:
  explicit PrescribedMotion(PrescribedMotionSpec s) : s_(std::move(s)) {}
  RigidPose pose(Real t) const;
  Vec3 velocity(Real t) const;          // of the pivot
  Vec3 angular_velocity(Real t) const;  // in grid axes
  RigidMotionSample sample(Real t) const { return {pose(t), velocity(t), angular_velocity(t)}; }
  const Vec3& pivot() const { return s_.pivot; }

 private:
  // The six coordinates (x, y, z, roll, pitch, yaw) at t and their rates.
  std::array<Real, 6> coordinates(Real t, bool rates) const;
  PrescribedMotionSpec s_;
};

}  // namespace narwhal

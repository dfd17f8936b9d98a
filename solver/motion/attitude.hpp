#pragma once
// Attitude of a rigid body by a unit quaternion e = (e0; e1, e2, e3), scalar first,
// rotating body axes to earth axes (NUMERICS §11.3–11.4): a_E = R(e) a_B. Earth axes
// are north-east-down, so gravity is +z_E. Euler angles are ZYX (yaw psi, pitch theta,
// roll phi) and used for input and output only; the integration never sees them, so
// it has no singularity at theta = ±90 degrees.
#include "core/types.hpp"

namespace narwhal {

using Quaternion = Eigen::Matrix<Real, 4, 1>;

struct EulerAngles {
  Real roll = 0.0;   // phi
  Real pitch = 0.0;  // theta
  Real yaw = 0.0;    // psi
};

// S(a) with S(a) b = a x b (§11.2's skew-symmetric matrix; also R-dot = R S(omega), §11.4).
Mat3 cross_product_matrix(const Vec3& a);

// §11.3: body -> earth rotation matrix.
Mat3 rotation_matrix(const Quaternion& e);

// §11.3: the earth "down" unit vector in body axes, R^T z_E (the third row of R).
Vec3 down_in_body(const Quaternion& e);

// §11.4: de/dt for body angular velocity omega = (p, q, r).
Quaternion quaternion_rate(const Quaternion& e, const Vec3& omega);

// §11.4: initialisation from and output to ZYX Euler angles (radians).
Quaternion quaternion_from_euler(const EulerAngles& a);
// The unit quaternion (e0 >= 0) of a rotation matrix: rotation_matrix(quaternion_from_rotation(R)) = R.
Quaternion quaternion_from_rotation(const Mat3& r);
EulerAngles euler_from_quaternion(const Quaternion& e);

}  // namespace narwhal

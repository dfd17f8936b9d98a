#include "motion/attitude.hpp"

#include <algorithm>
#include <cmath>

namespace narwhal {

Mat3 cross_product_matrix(const Vec3& a) {
  Mat3 s;
  s << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
  return s;
}

Mat3 rotation_matrix(const Quaternion& e) {
  const Real e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
  Mat3 r;
  r << 1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2),  //
      2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1),   //
      2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2);
  return r;
}

Vec3 down_in_body(const Quaternion& e) {
  const Real e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
  return {2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)};
}

Quaternion quaternion_rate(const Quaternion& e, const Vec3& w) {
  const Real e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
  const Real p = w[0], q = w[1], r = w[2];
  return 0.5 * Quaternion(-e1 * p - e2 * q - e3 * r,  //
                          e0 * p - e3 * q + e2 * r,   //
                          e3 * p + e0 * q - e1 * r,   //
                          -e2 * p + e1 * q + e0 * r);
}

Quaternion quaternion_from_euler(const EulerAngles& a) {
  const Real cf = std::cos(0.5 * a.roll), sf = std::sin(0.5 * a.roll);
  const Real ct = std::cos(0.5 * a.pitch), st = std::sin(0.5 * a.pitch);
  const Real cp = std::cos(0.5 * a.yaw), sp = std::sin(0.5 * a.yaw);
  return {cf * ct * cp + sf * st * sp,  //
          sf * ct * cp - cf * st * sp,  //
          cf * st * cp + sf * ct * sp,  //
          cf * ct * sp - sf * st * cp};
}

EulerAngles euler_from_quaternion(const Quaternion& e) {
  const Real e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
  EulerAngles a;
  a.roll = std::atan2(2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2));
  a.pitch = std::asin(std::clamp(2 * (e0 * e2 - e1 * e3), Real(-1), Real(1)));
  a.yaw = std::atan2(2 * (e1 * e2 + e0 * e3), 1 - 2 * (e2 * e2 + e3 * e3));
  return a;
}

Quaternion quaternion_from_rotation(const Mat3& r) {
  const Eigen::Quaternion<Real> q(r);  // Eigen's unit quaternion has §11.3's R
  Quaternion e(q.w(), q.x(), q.y(), q.z());
  return e[0] < 0.0 ? Quaternion(-e) : e;
}

}  // namespace narwhal

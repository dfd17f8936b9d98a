// Force integration (§4.5): the pressure and friction parts of every coefficient.
#include <gtest/gtest.h>

#include <vector>

#include "physics/wall_forces.hpp"

namespace narwhal {
namespace {

WallFace face(const Vec3& x, const Vec3& n, Real area, Real cp, const Vec3& cf) {
  WallFace w;
  w.x = x;
  w.n = n;
  w.area = area;
  w.cp = cp;
  w.cf = cf;
  return w;
}

// Two faces of a body whose pressure pushes in z and whose friction drags in x:
// each part by hand, the total their sum.
TEST(WallForces, PressureAndFrictionPartsAreSeparateAndAddUpToTheTotal) {
  const std::vector<WallFace> faces = {
      face({1.0, 0.0, 0.5}, {0.0, 0.0, 1.0}, 0.2, -0.4, {0.006, 0.0, 0.0}),
      face({2.0, 0.0, -0.5}, {0.0, 0.0, -1.0}, 0.3, 0.1, {0.004, 0.0, 0.001}),
  };
  const Real area_ref = 0.5, length_ref = 2.0;
  const Vec3 centre(1.5, 0.0, 0.0);
  const ForceCoefficients c = integrate_forces(faces, area_ref, length_ref, centre);
  // -p n A / (A_ref / 2) per face, in coefficient form: -cp n A / A_ref.
  const Vec3 p0 = -(-0.4) * Vec3(0, 0, 1) * 0.2 / area_ref, p1 = -(0.1) * Vec3(0, 0, -1) * 0.3 / area_ref;
  const Vec3 f0 = Vec3(0.006, 0, 0) * 0.2 / area_ref, f1 = Vec3(0.004, 0, 0.001) * 0.3 / area_ref;
  const Vec3 r0 = Vec3(1.0, 0.0, 0.5) - centre, r1 = Vec3(2.0, 0.0, -0.5) - centre;
  EXPECT_NEAR((c.pressure_force - (p0 + p1)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((c.friction_force() - (f0 + f1)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((c.pressure_moment - (r0.cross(p0) + r1.cross(p1)) / length_ref).norm(), 0.0, 1e-15);
  EXPECT_NEAR((c.friction_moment() - (r0.cross(f0) + r1.cross(f1)) / length_ref).norm(), 0.0, 1e-15);
  EXPECT_NEAR((c.force - (p0 + p1 + f0 + f1)).norm(), 0.0, 1e-15);
  EXPECT_GT(c.pressure_force.z(), 0.0);  // suction on the upper face, push on the lower: lift up
  EXPECT_EQ(c.pressure_force.x(), 0.0);  // no pressure drag from faces normal to z
}

}  // namespace
}  // namespace narwhal

// Force integration (§4.5): the pressure and friction parts of every coefficient.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <fmt/format.h>

#include "app/driver.hpp"
#include "bc/boundary.hpp"
#include "physics/wall_forces.hpp"
#include "test_support.hpp"

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

// Pressure on a sphere acts through its centre: it has no moment about it, whatever the
// pressure. The faceted sphere's faces are not quite normal to their radii, so a pressure
// that pushes the fore and aft halves sideways in opposite senses (no net force) turns
// it: the discretization's moment, which must vanish at second order with the grid. It
// matters on coarse grids: it is of the size of the viscous torque that turns a falling
// sphere (solver/motion/DESIGN.md).
Real pressure_moment_about_the_centre(int coarsen) {
  const std::string text = test::read_text(test::source_path("validation/cases/sphere_free_fall/sphere_free_fall.toml"));
  const CaseConfig c = parse_case(text, "sphere_free_fall.toml", ".", {fmt::format("grid.coarsen={}", coarsen)});
  Grid g = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f;
  f.allocate(g, fp, c.initial);
  const Vec3 centre(0.5, 0.0, 0.0);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      const Vec3 r = g.blocks[ib].xc(Index3{i, j, k}) - centre;
      f.Q[ib](i, j, k)[0] = 4.0 * r.y() * r.x();
    });
  fill_ghosts(g, f, fp);
  const auto groups = wall_faces(g, f, fp);
  const ForceCoefficients body = integrate_forces(groups.at("body"), 1.0, 1.0, centre);
  EXPECT_LT(body.pressure_force.norm(), 1e-12);
  return body.pressure_moment.norm();
}

TEST(WallForces, PressureMomentOfASphereAboutItsCentreVanishesAtSecondOrder) {
  const Real coarse = pressure_moment_about_the_centre(2), medium = pressure_moment_about_the_centre(1);
  const Real order = std::log2(coarse / medium);
  std::printf("pressure moment about a sphere's centre: %.3e (coarse), %.3e (medium), order %.2f\n", coarse, medium,
              order);
  EXPECT_GT(order, 1.8);
  EXPECT_GT(coarse, 0.0);  // a faceted body: not zero by construction
}

}  // namespace
}  // namespace narwhal

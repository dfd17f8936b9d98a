#include "motion/rigid_body.hpp"

#include <cmath>

#include "core/error.hpp"

namespace narwhal {

BodyLoads operator+(BodyLoads a, const BodyLoads& b) { return a += b; }
BodyLoads operator*(Real s, const BodyLoads& a) { return {s * a.force, s * a.moment}; }

RigidBodyState RigidBodyState::at_rest(const Vec3& position, const EulerAngles& attitude) {
  RigidBodyState s;
  s.attitude() = quaternion_from_euler(attitude);
  s.position() = position;
  return s;
}

RigidBodyEquations::RigidBodyEquations(const MassProperties& mp, const AccelerationOptions& options)
    : mp_(mp), options_(options) {
  if (!(mp.mass > 0.0) || !std::isfinite(mp.mass)) fail("rigid body: mass must be positive and finite, got {}", mp.mass);
  if (!(mp.weight >= 0.0) || !(mp.buoyancy >= 0.0))
    fail("rigid body: weight and buoyancy must be non-negative, got W = {}, B = {}", mp.weight, mp.buoyancy);
  if (!mp.down.allFinite() || std::abs(mp.down.norm() - 1.0) > 1e-12)
    fail("rigid body: the down direction must be a unit vector, got ({}, {}, {})", mp.down[0], mp.down[1], mp.down[2]);
  if (!mp.inertia_o.allFinite() || (mp.inertia_o - mp.inertia_o.transpose()).norm() > 1e-12 * mp.inertia_o.norm())
    fail("rigid body: the inertia tensor about O must be finite and symmetric");
  // §11.2: M_RB = [m I, -m S(r_G); m S(r_G), I_O], symmetric because S(r_G)^T = -S(r_G).
  const Mat3 s = cross_product_matrix(mp.r_g);
  m_rb_.setZero();
  m_rb_.topLeftCorner<3, 3>() = mp.mass * Mat3::Identity();
  m_rb_.topRightCorner<3, 3>() = -mp.mass * s;
  m_rb_.bottomLeftCorner<3, 3>() = mp.mass * s;
  m_rb_.bottomRightCorner<3, 3>() = mp.inertia_o;
  // M_RB is positive definite exactly when the inertia about G, I_O - m S(r_G)^T S(r_G),
  // is (the Schur complement): a body whose stated inertia about O is smaller than the
  // parallel-axis part of its CG offset is not a physical body.
  const Mat3 inertia_g = mp.inertia_o - mp.mass * s.transpose() * s;
  Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia_g);
  if (eig.eigenvalues().minCoeff() <= 0.0)
    fail("rigid body: the inertia about the centre of gravity (I_O minus the parallel-axis term of r_G) must be "
         "positive definite; smallest principal value {}",
         eig.eigenvalues().minCoeff());
  const Mat6& ma = options.added_mass_estimate;
  if (!ma.allFinite() || (ma - ma.transpose()).norm() > 1e-12 * std::max<Real>(ma.norm(), 1e-300) ||
      Eigen::SelfAdjointEigenSolver<Mat6>(ma).eigenvalues().minCoeff() < -1e-12 * ma.norm())
    fail("rigid body: the added-mass estimate must be symmetric positive semi-definite");
  Mat6 m = m_rb_ + ma;
  for (int d = 0; d < 6; ++d)
    if (!options.free[d]) {
      m.row(d).setZero();
      m.col(d).setZero();
      m(d, d) = 1.0;
    }
  solve_factor_.compute(m);
}

BodyLoads RigidBodyEquations::hydrostatic_loads(const RigidBodyState& s) const {
  const Vec3 down = rotation_matrix(s.attitude()).transpose() * mp_.down;
  BodyLoads h;
  h.force = (mp_.weight - mp_.buoyancy) * down;
  h.moment = mp_.r_g.cross(mp_.weight * down) - mp_.r_b.cross(mp_.buoyancy * down);
  return h;
}

Vec6 RigidBodyEquations::accelerations(const Vec3& v, const Vec3& w, const BodyLoads& total) const {
  Vec6 rhs;
  rhs.head<3>() = total.force - mp_.mass * (w.cross(v) + w.cross(w.cross(mp_.r_g)));
  rhs.tail<3>() = total.moment - w.cross(mp_.inertia_o * w) - mp_.mass * mp_.r_g.cross(w.cross(v));
  for (int d = 0; d < 6; ++d)
    if (!options_.free[d]) rhs[d] = 0.0;
  return solve_factor_.solve(rhs);
}

RigidBodyState RigidBodyEquations::derivative(const RigidBodyState& s, const BodyLoads& loads) const {
  const Vec3 v = s.velocity(), w = s.angular_velocity();
  const Quaternion e = s.attitude();
  RigidBodyState d;
  d.y.head<6>() = accelerations(v, w, loads + hydrostatic_loads(s));
  d.attitude() = quaternion_rate(e, w);
  d.position() = rotation_matrix(e) * v;
  return d;
}

Real RigidBodyEquations::kinetic_energy(const RigidBodyState& s) const {
  const Vec6 nu = s.y.head<6>();
  return 0.5 * nu.dot(m_rb_ * nu);
}

Vec3 RigidBodyEquations::linear_momentum_body(const RigidBodyState& s) const {
  return (m_rb_ * s.y.head<6>()).head<3>();
}

Vec3 RigidBodyEquations::angular_momentum_body(const RigidBodyState& s) const {
  return (m_rb_ * s.y.head<6>()).tail<3>();
}

}  // namespace narwhal

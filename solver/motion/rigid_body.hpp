#pragma once
// Six-degree-of-freedom rigid body in body axes (NUMERICS §11.1–11.4; the standard
// submarine equations of Gertler & Hagen 1967 / Feldman 1979 in the vector form of
// Fossen 1994, with the body origin O anywhere: the CG offset r_G couples translation
// and rotation through the constant rigid-body mass matrix M_RB).
//
//   M_RB [dv/dt; dw/dt] = [F_B - m(w x v + w x (w x r_G));
//                          M_O,B - w x (I_O w) - m r_G x (w x v)]
//   de/dt = 1/2 E(e) w,   dx_O/dt = R(e) v
//
// State (13): v = (u, v, w) of O relative to earth in body axes, w = (p, q, r), the
// quaternion e, the position x_O in earth axes. Loads F_B, M_O,B are in body axes,
// moments about O. Hydrostatics (§11.3): weight W at G and buoyancy B at the centre of
// buoyancy r_B act along the earth's down direction.
// Units are the caller's, consistently (the flow solver's nondimensional ones: §0.2).
// Earth axes are §11's north-east-down unless MassProperties::down says where down is
// (a flow solver's grid axes serve as earth axes with their own "down").
//
// For the coupling with a flow solver (§11.7) the accelerations can be solved with
// degrees of freedom held (their accelerations zero) and with an added-mass estimate
// M_A on the left, M_RB + M_A: the coupling puts M_A times its previous estimate of the
// accelerations among the loads, so that where its iteration has converged the
// unmodified equations hold (AccelerationOptions).
//
// Usage:
//   MassProperties mp{.mass = 1.0, .inertia_o = I, .weight = W, .buoyancy = W};
//   RigidBodyEquations body(mp);              // validates, factorises M_RB once
//   RigidBodyState s = RigidBodyState::at_rest(Vec3::Zero(), EulerAngles{});
//   RigidBodyState dsdt = body.derivative(s, external_loads);
#include <array>

#include "core/types.hpp"
#include "motion/attitude.hpp"

namespace narwhal {

struct MassProperties {
  Real mass = 0.0;
  Vec3 r_g = Vec3::Zero();         // centre of gravity relative to O, body axes
  Vec3 r_b = Vec3::Zero();         // centre of buoyancy relative to O, body axes
  Mat3 inertia_o = Mat3::Zero();   // inertia tensor about O: diag (I_x, I_y, I_z), off-diagonal -I_xy ...
  Real weight = 0.0;               // W = m g
  Real buoyancy = 0.0;             // B = rho g (displaced volume)
  Vec3 down = Vec3::UnitZ();       // where gravity points, earth axes (unit)
};

using Vec6 = Eigen::Matrix<Real, 6, 1>;
using Mat6 = Eigen::Matrix<Real, 6, 6>;

// Degrees of freedom in §11.1's order (u, v, w, p, q, r): surge, sway, heave along the
// body axes, roll, pitch, yaw about them.
struct AccelerationOptions {
  std::array<bool, 6> free{true, true, true, true, true, true};  // false: held (acceleration zero)
  Mat6 added_mass_estimate = Mat6::Zero();                       // M_A of §11.7, body axes, about O
};

// Loads in body axes; the moment is about the body origin O.
struct BodyLoads {
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  BodyLoads& operator+=(const BodyLoads& o) {
    force += o.force;
    moment += o.moment;
    return *this;
  }
};
BodyLoads operator+(BodyLoads a, const BodyLoads& b);
BodyLoads operator*(Real s, const BodyLoads& a);

using RigidBodyVector = Eigen::Matrix<Real, 13, 1>;

// The 13 ODE unknowns of §11.1, stored contiguously so that RK4 works on one vector.
struct RigidBodyState {
  RigidBodyVector y = RigidBodyVector::Zero();

  static RigidBodyState at_rest(const Vec3& position, const EulerAngles& attitude);

  auto velocity() { return y.segment<3>(0); }
  auto velocity() const { return y.segment<3>(0); }
  auto angular_velocity() { return y.segment<3>(3); }
  auto angular_velocity() const { return y.segment<3>(3); }
  auto attitude() { return y.segment<4>(6); }
  auto attitude() const { return y.segment<4>(6); }
  auto position() { return y.segment<3>(10); }
  auto position() const { return y.segment<3>(10); }
};

class RigidBodyEquations {
 public:
  // Throws Error naming the offending property when the mass is not positive, the
  // inertia tensor is not symmetric positive definite, W, B are negative or `down` is
  // not a unit vector,
  // and when the added-mass estimate is not symmetric positive semi-definite.
  explicit RigidBodyEquations(const MassProperties& mp, const AccelerationOptions& options = {});

  const MassProperties& mass_properties() const { return mp_; }
  const AccelerationOptions& options() const { return options_; }
  const Mat6& mass_matrix() const { return m_rb_; }

  // §11.3: weight at G and buoyancy at B for the state's attitude, body axes, about O.
  BodyLoads hydrostatic_loads(const RigidBodyState& s) const;

  // §11.2 + §11.4: d(state)/dt under the given loads plus hydrostatics.
  RigidBodyState derivative(const RigidBodyState& s, const BodyLoads& loads) const;

  // Accelerations (dv/dt, dw/dt) of §11.2 alone, for the coupling and for tests: those
  // of the held degrees of freedom zero, the others solved with M_RB + M_A.
  Vec6 accelerations(const Vec3& v, const Vec3& w, const BodyLoads& total) const;

  // Kinetic energy 1/2 [v; w]^T M_RB [v; w] and the linear and angular momentum about O
  // in body axes: invariants of the torque-free body, for the health checks and tests.
  Real kinetic_energy(const RigidBodyState& s) const;
  Vec3 linear_momentum_body(const RigidBodyState& s) const;
  Vec3 angular_momentum_body(const RigidBodyState& s) const;

 private:
  MassProperties mp_;
  AccelerationOptions options_;
  Mat6 m_rb_;
  // M_RB + M_A with the held degrees of freedom's rows and columns replaced by the
  // identity's (their right-hand sides zeroed): the free ones' reduced system.
  Eigen::LDLT<Mat6> solve_factor_;
};

}  // namespace narwhal

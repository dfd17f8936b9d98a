#pragma once
// A free body driven by a dual-time flow solution, strongly coupled (NUMERICS §11.6,
// §11.7). Each physical step
//   * begin_step: predicts y^{n+1} by RK4 from y^n with the flow loads extrapolated,
//     F^{n+1,*} = 2 F^n - F^{n-1} (F^n at the first step; the first step's stages all
//     take F^{n+1,*}: the loads jump at release);
//   * correct, after each of the flow's sub-iterations: redoes the RK4 step from y^n
//     with the flow's latest loads F^{n+1,m} and under-relaxes,
//       y^{n+1,m+1} = y^{n+1,m} + omega_b (y_RK4 - y^{n+1,m});
//     the step's motion has converged when the velocities (u ... r, body axes) change
//     by less than the tolerance.
// The body's position and attitude follow the flow's time scheme, not RK4's: the grid
// must move so that its faces' speeds (swept volumes: the BDF derivative of the node
// positions, motion/grid_motion.hpp) are the body's velocities, so
//   c0 dx^{n+1} - c2 dx^n = h V_E^{n+1},   c0 dphi^{n+1} - c2 dphi^n = h omega_E^{n+1}
// (dx the origin's step, dphi the rotation vector of the step's turn, earth axes; RK4
// gives the velocities). With RK4's own positions the wall's speed would be the BDF
// derivative of them, which, through the added mass, feeds an odd-even mode from step
// to step: a sphere of density ratio 1.5 released in still fluid saw its force
// alternate with growing amplitude (x1.3 per step).
//
// Added-mass stabilisation: RigidBodyEquations solves the accelerations with
// M_RB + M_A (AccelerationOptions::added_mass_estimate) and every RK4 stage gets
// M_A times that stage's acceleration of the previous pass among its loads, so that a
// converged iteration solves the unmodified equations (§11.7's preconditioner).
//
// Stability of the iteration, measured against a fluid force -m_a (V^{n+1} - V^n)/dt
// that answers the estimate at once (tests/motion/coupled_body_test.cpp): an iterate's
// error is multiplied by 1 - omega_b (1 + w m_a / m) per correction, w the weight the
// RK4 stages give F^{n+1,*}: 1/2 in a step (stable for omega_b < 2 / (1 + m_a / (2 m)),
// m_a / m < 2 at omega_b = 1), 1 in the first step after release (m_a / m < 1 at
// omega_b = 1). A neutrally buoyant sphere has m_a / m = 0.5, a 6:1 spheroid broadside
// 0.96. With the estimate M_A = m_a the first step converges at once and the factor
// after it is m_a / (2 (m + m_a)) < 1/2, whatever the mass ratio. A flow's force
// answers a BDF2 step more strongly (by 3/2): the limits scale accordingly.

// Frames: earth axes are the grid's axes as built; the body's axes at t = 0 those of
// motion/grid_axes.hpp (x_B = -x, y_B = -y, z_B = z), so that the grid as built is the
// body's initial pose. Loads come in earth axes about the body origin O at the
// estimate's position and go to body axes with the estimate's attitude.
#include <array>
#include <vector>

#include "motion/ballast.hpp"
#include "motion/trim.hpp"
#include "motion/grid_motion.hpp"
#include "motion/rk4.hpp"

namespace narwhal {

struct CouplingSettings {
  Real relaxation = 1.0;  // omega_b
  Real tolerance = 1e-6;  // on the velocities' change per correction
};

// The state of a body whose axes are grid_axes.hpp's, O at `origin` (grid
// coordinates), moving with `velocity` and turning with `angular_velocity` (grid axes).
RigidBodyState body_state_at_release(const Vec3& origin, const Vec3& velocity, const Vec3& angular_velocity);

// The grid's pose (from as built), its pivot's velocity and its angular velocity in grid
// axes, for a body in state `s` whose axes at release were `initial_rotation`, O then at `pivot`.
RigidMotionSample motion_sample(const RigidBodyState& s, const Mat3& initial_rotation, const Vec3& pivot);

class CoupledBody {
 public:
  // The body in state `initial` (body_state_at_release: the grid as built is its pose).
  // `ballast`: changes of weight in time (motion/ballast.hpp), evaluated at every RK4
  // stage with the hydrostatics.
  CoupledBody(const MassProperties& mp, const AccelerationOptions& options, const RigidBodyState& initial,
              const CouplingSettings& settings, std::vector<BallastChange> ballast = {}, TrimSpec trim = {});

  // The flow's loads on the initial state (earth axes, about O): F^0, which the first
  // step's predictor takes (none given: zero, as on a body released in still fluid).
  // Before the first step, the trim (TrimSpec) is found from them.
  void observe_initial_loads(const BodyLoads& flow_earth);
  const TrimWeights& trim() const { return trim_weights_; }
  // §11.6-11.7 predictor for the step from t^n = time to t^n + step, which the flow
  // takes with BDF coefficients c: the estimate of the last step (and its latest loads)
  // becomes y^n (F^n).
  void begin_step(Real time, Real step, const BdfCoefficients& c);
  // Corrector from the flow's loads at the estimate (earth axes, about O there);
  // returns the largest change it made to a velocity component.
  Real correct(const BodyLoads& flow_earth);
  bool converged(Real change) const { return change < settings_.tolerance; }

  const RigidBodyState& state() const { return estimate_; }  // y^{n+1} as estimated
  const RigidBodyState& start_of_step() const { return y_n_; }
  const BodyLoads& flow_loads() const { return f_latest_; }   // body axes, the latest
  const RigidBodyEquations& equations() const { return body_; }
  Real quaternion_norm_error() const { return norm_error_; }

  // The pose of the grid (from as built), its pivot's velocity and its angular velocity
  // in grid axes, for a state of this body.
  RigidMotionSample sample(const RigidBodyState& s) const;
  // The ZYX Euler angles of the turn from the body's axes at release to those of `s`,
  // in the axes at release (NUMERICS §11.4's order).
  EulerAngles turn_since_release(const RigidBodyState& s) const;
  const Vec3& pivot() const { return pivot_; }

  // Everything a restart needs to continue bit for bit (both states, the loads of two
  // levels, the last pass's stage accelerations, the trim), as one flat list.
  std::vector<Real> checkpoint() const;
  void restore(const std::vector<Real>& values);  // throws Error on a list of another length

 private:
  RigidBodyStep rk4_pass(const BodyLoads& f_next);  // RK4 velocities, the flow's kinematics
  BodyLoads to_body_axes(const BodyLoads& earth) const;
  Vec3 down_body(const RigidBodyState& at) const;  // gravity's direction in body axes
  void find_trim();

  RigidBodyEquations body_;
  CouplingSettings settings_;
  std::vector<BallastChange> ballast_;
  TrimSpec trim_;
  TrimWeights trim_weights_;
  Vec3 pivot_;
  Mat3 initial_rotation_;
  RigidBodyState y_n_, estimate_;
  BodyLoads f_n_, f_nm1_, f_latest_;  // body axes about O
  int steps_ = 0;                     // steps begun
  std::array<Vec6, 4> stage_acc_{Vec6::Zero(), Vec6::Zero(), Vec6::Zero(), Vec6::Zero()};
  Real time_ = 0.0, step_ = 0.0, norm_error_ = 0.0;
  BdfCoefficients bdf_;
  Vec3 dx_n_ = Vec3::Zero(), dphi_n_ = Vec3::Zero();  // the last step's displacement and turn (earth axes)
};

}  // namespace narwhal

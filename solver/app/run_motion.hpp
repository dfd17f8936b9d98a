#pragma once
// How a dual-time run's grids move (NUMERICS §6.8 step 2, §11.7): along a prescribed
// motion, or with a free body whose equations the flow's loads drive, strongly coupled
// (motion/coupled_body.hpp): predicted when a step begins, corrected after every
// sub-iteration and the grids moved again, from the same t^n. Every grid the run keeps
// moves together: each multigrid level (its own GCL, §7.1) and the case's own blocks
// when the run computes on pieces of them.
#include <memory>
#include <vector>

#include "config/case_config.hpp"
#include "io/restart.hpp"
#include "motion/coupled_body.hpp"
#include "motion/grid_motion.hpp"
#include "motion/prescribed_motion.hpp"

namespace narwhal {

class RunMotion {
 public:
  // `grids`: every grid that moves; grids[described] is the one the run's files
  // describe (the case's blocks: the finest level, or the whole when the run computes
  // on pieces).
  RunMotion(const CaseConfig& c, const std::vector<Grid*>& grids, std::size_t described);

  bool free_body() const { return body_ != nullptr; }
  const CoupledBody& body() const { return *body_; }  // free_body() only

  // t = 0: the grids at the starting pose (and their present shapes).
  void place_at_start();
  // Then a free body takes the flow's loads on the initial state (earth axes, about its
  // origin).
  void start(const BodyLoads& loads);
  // A step's first move, from t^n to t^{n+1} = t^n + dt: a free body predicted.
  void begin_step(Real t_n, Real dt, const BdfCoefficients& c);
  // A free body after a sub-iteration: corrected from the flow's loads on it (earth
  // axes, about its present origin), the grids moved again. Returns the velocities'
  // change; coupled() says whether it is below the tolerance.
  Real correct(const BodyLoads& loads, Real dt, const BdfCoefficients& c);
  bool coupled(Real change) const { return !body_ || body_->converged(change); }

  // The grids' pose, pivot velocity and angular velocity now (grid axes).
  RigidMotionSample sample() const { return present(); }
  const Vec3& pivot() const { return pivot_; }
  // New shapes (nodes as built) for every grid, in the order the constructor took them
  // (control surfaces turned): the next move carries the grids there.
  void reshape_all(std::vector<std::vector<GhostArray<Vec3>>> shapes);
  // Where a point of the body (of the grid as built) is now.
  Vec3 now(const Vec3& as_built) const;
  // The body origin now: the point a free body's moments are taken about.
  Vec3 origin() const { return now(pivot_); }

  // Restarts: the body's state, and the grids placed at t^{n-1} (the time levels take
  // V^{n-1} there), then moved to t^n as step n moved them.
  std::vector<Real> checkpoint() const;
  void place_at_previous_level(const RestartInfo& info, Real dt);
  void move_to_present_level(const RestartInfo& info, Real dt, const BdfCoefficients& c);
  std::vector<std::array<double, 6>> reference_extents() const { return moving_[described_]->reference_extents(); }

 private:
  RigidMotionSample present() const;  // the motion at the time of the state the grids are at
  void move_all(const RigidMotionSample& m, Real dt, const BdfCoefficients& c, bool new_step);

  std::unique_ptr<PrescribedMotion> prescribed_;
  std::unique_ptr<CoupledBody> body_;
  Vec3 pivot_;
  Real time_ = 0.0;  // t^{n+1} of the step under way (prescribed motion)
  std::vector<std::unique_ptr<MovingGrid>> moving_;
  std::size_t described_ = 0;  // the grid the run's files describe
};

}  // namespace narwhal

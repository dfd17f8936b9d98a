#pragma once
// The physical-time levels of a dual-time run (NUMERICS §2.5, §6.8): t^n, the states
// Q^n and Q^{n-1} (with the transport turbulence models' variables, when the run has
// them) and volumes V^n and V^{n-1} of the owned blocks, and the steps taken.
// begin_step moves a step on: the state reached becomes Q^n, the BDF coefficients are
// set (BDF2 starts with a BDF1 step: there is no Q^{n-1} yet) and the finest level's
// physical-time term gets its old levels' part. The state itself is the guess
// Q^{n+1,0} = Q^n (§6.2).
#include "config/case_config.hpp"
#include "implicit/physical_time.hpp"
#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

class DualTime {
 public:
  DualTime(const Grid& g, const TimeConfig& tc);

  void begin_step(const Grid& g, const FlowField& f);

  // The coefficients step `n` (1, 2, ...) uses: BDF1 for a BDF1 run and for a BDF2 run's
  // first step.
  BdfCoefficients coefficients_of_step(int n) const;

  // For a restart: Q^{n-1} (and the turbulence variables' level n-1) into f (owned
  // blocks), and back. restore() takes the volumes V^{n-1} from `g` as it stands: place
  // a moving grid at t^{n-1} first.
  void save_previous(const Grid& g, FlowField& f) const;
  void restore(const Grid& g, const FlowField& previous, int step, Real time);

  // The finest level's physical-time term (the solver holds a pointer to it).
  const PhysicalTimeTerm& term() const { return term_; }
  int step() const { return step_; }          // steps begun
  Real time() const { return time_; }         // t^{n+1} of the step under way (t^0 = 0 before any)
  Real step_size() const { return tc_.step; }

 private:
  TimeConfig tc_;
  PhysicalTimeTerm term_;
  int step_ = 0;
  Real time_ = 0.0;
  Real previous_step_ = 0.0;  // dt_{n-1}; 0: none yet
  std::vector<GhostArray<State>> q_n_, q_nm1_;
  std::vector<GhostArray<TurbState>> turb_n_, turb_nm1_;  // empty: no transport turbulence model
  std::vector<GhostArray<Real>> vol_n_, vol_nm1_;
};

}  // namespace narwhal

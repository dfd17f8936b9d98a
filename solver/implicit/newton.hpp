#pragma once
// Discretized Newton relaxation (NUMERICS §6): first-order numerical face
// Jacobians (§6.3), 7-point block matrix (§6.4), symmetric Gauss-Seidel sweeps
// (§6.5), local pseudo-time step with switched-evolution-relaxation CFL (§6.6).
#include <array>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "implicit/cfl_control.hpp"
#include "implicit/physical_time.hpp"
#include "mesh/block.hpp"
#include "parallel/communicator.hpp"
#include "physics/flow.hpp"

namespace narwhal {

struct NewtonSettings {
  Real cfl_start = 10.0;
  Real cfl_max = 1.0e6;
  // The largest factor by which SER may raise the CFL from one iteration to the next
  // (0: no limit, §6.6 as written). The SER CFL follows the residual's first fall, which
  // from a uniform stream is fast: 1 to 1e3 in about nine SUBOFF cycles, faster than the
  // wall layers' k and omega settle, and some such starts diverged (mesh/DESIGN.md).
  Real cfl_growth = 0.0;
  int sgs_iterations = 3;   // forward+backward pairs per Newton iteration
  Real fd_epsilon = 1e-7;   // finite-difference step of the numerical Jacobians
  Real relaxation = 1.0;    // omega_N
  // A correction whose linearized residual |R + A dQ| exceeds |R| by this factor is
  // rejected and the CFL cut (NewtonSolver::relax_and_update). The limit separates
  // amplification from a poor but usable correction: healthy iterations leave 0.1-0.9
  // of the residual, the nonlinear duct's start 1.35 (and converges), a sweep diverging
  // at the SUBOFF nose square's corner 3e14.
  Real linear_growth_limit = 10.0;
  // A sustained residual rise beyond this lowers the CFL's ceiling (implicit/cfl_rise_guard.hpp).
  Real rise_limit = CflRiseGuard::kDefaultRiseLimit;
};

struct IterationNorms {
  std::array<Real, kNumEq> l2{};  // RMS over cells of R_c / V_c, per equation
  Real total = 0.0;              // sqrt of the sum of squares of l2
  Real cfl = 0.0;
};

// Thrown when a residual or state becomes non-finite or blows up; the message
// names block, cell and equation.
class DivergenceError : public Error {
 public:
  using Error::Error;
};

class NewtonSolver {
 public:
  // `comm`: the ranks g's blocks are distributed over. Every iteration is collective over it
  // (the residual norms, the SER CFL and the checks are sums and extrema over all blocks).
  NewtonSolver(Grid& g, FlowField& f, const FlowParams& fp, NewtonSettings s, const Communicator& comm);

  // One Newton iteration: BCs, residual, Jacobians, SGS, update. Returns the
  // norms of the residual evaluated at the start of the iteration. The CFL
  // follows switched evolution relaxation from the first residual (§6.6).
  IterationNorms iterate();

  // The same with a CFL number given from outside (multigrid levels use the
  // finest level's SER value).
  IterationNorms iterate_with_cfl(Real cfl, bool reuse_jacobian = false);

  // The Jacobian, SGS and update half of an iteration, for a residual that was
  // just evaluated (evaluate_residual) at the current state.
  // With `reuse_jacobian`, the block matrices of the previous iteration are kept
  // (same CFL): they only shape the path, not the converged answer.
  IterationNorms relax_and_update(IterationNorms n, Real cfl, bool reuse_jacobian = false);

  // Only the SGS sweeps (forward + backward pairs) with the matrices of the last
  // assembly; for benchmarks and linear-solver studies.
  void sweeps_only(int pairs);

  // Allow reusing matrices assembled at another CFL (Jacobian freezing across cycles).
  void allow_stale_cfl(bool ok) { stale_cfl_ok_ = ok; }

  // SER CFL for a residual norm (§6.6), its growth limited by cfl_growth (after a
  // rejected correction by kRecoveryGrowth at least), under the rise guard's ceiling;
  // fixes the reference norm on first use.
  Real ser_cfl(Real norm);

  // FAS forcing f (§7.2): the smoother then drives R(Q) - f to zero. nullptr: none.
  void set_forcing(const std::vector<GhostArray<State>>* f) { forcing_ = f; }

  // Dual time stepping (§6.1): the physical-time term joins the residual and the
  // diagonal blocks (R* instead of R). nullptr: a steady problem.
  void set_physical_time(const PhysicalTimeTerm* t) { time_ = t; }

  // Residual of the current state (fills ghosts), without updating.
  IterationNorms evaluate_residual();

  // The CFL controller's state, saved in restarts and restored whole, so that a continued
  // run follows the same path.
  CflControlState cfl_control() const { return {ref_norm_, last_cfl_, recovering_, guard_.state()}; }
  void restore_cfl_control(const CflControlState& c) {
    ref_norm_ = c.reference_norm;
    last_cfl_ = c.last_cfl;
    recovering_ = c.recovering;
    guard_.restore(c.rise_guard);
  }
  // A retreat from a divergence (app/retreat.hpp) caps SER's CFL from here on.
  void lower_cfl_ceiling(Real ceiling) { guard_.lower_ceiling(ceiling); }
  Real reference_norm() const { return ref_norm_; }
  // The CFL ceiling that sustained residual rises lower (ser_cfl).
  const CflRiseGuard& rise_guard() const { return guard_; }

  // R(Q) - f of the last evaluation (cell-integrated, no ghosts).
  const std::vector<GhostArray<State>>& residual() const { return R_; }

  // RMS over cells of (R + A dQ)/V for the last assembly's system and correction, over
  // `nonlinear_total` (that of R/V): 1 for no correction, 0 for the exact one. A sum over
  // all ranks in block order.
  Real linear_residual_ratio_collective(Real nonlinear_total) const;

  // How many times a correction was rejected and the CFL cut (relax_and_update).
  int cfl_cuts() const { return cfl_cuts_; }

  // Checks every residual and state entry; throws DivergenceError naming the
  // first non-finite one, on every rank (collective over comm_).
  void check_finite() const;

  // "block 'b' cell (i, j, k), equation u: |R|/V = ..." for the largest residual of
  // `equation` (-1: of any). Collective over comm_.
  std::string describe_largest_residual(int equation = -1) const;

 private:
  void assemble_block(int ib, Real cfl);
  void sweep_block(int ib, bool forward);
  IterationNorms norms() const;  // collective over comm_
  State linear_residual(int ib, const Index3& c) const;
  std::string describe_largest_linear_residual_collective() const;

  // A rejected correction (NewtonSettings::linear_growth_limit) cuts the CFL by kCflCut, at most kMaxCflCuts - 1 times in one
  // iteration (1e3 down to 0.24); the SER CFL then regrows by kRecoveryGrowth at most
  // per iteration unless cfl_growth already limits it.
  static constexpr Real kCflCut = 0.25;
  static constexpr int kMaxCflCuts = 7;
  static constexpr Real kRecoveryGrowth = 1.5;

  Grid& g_;
  FlowField& f_;
  FlowParams fp_;
  NewtonSettings s_;
  Communicator comm_;
  Real ref_norm_ = -1.0;
  Real last_cfl_ = -1.0;  // < 0: none yet
  bool recovering_ = false;  // the CFL was cut and has not yet regrown to SER's value
  int cfl_cuts_ = 0;
  CflRiseGuard guard_;
  const std::vector<GhostArray<State>>* forcing_ = nullptr;
  const PhysicalTimeTerm* time_ = nullptr;
  bool assembled_ = false;
  bool stale_cfl_ok_ = false;
  Real assembled_cfl_ = 0.0;
  std::vector<GhostArray<State>> R_;
  std::vector<GhostArray<State>> dQ_;
  std::vector<GhostArray<Mat4>> Dinv_;
  std::vector<std::array<GhostArray<Mat4>, 3>> AL_, AR_;
};

}  // namespace narwhal
